//! A map from id to value holding at most `capacity` entries: when full, the least recently used entry is
//! forgotten first. It also remembers (within a bounded budget) which ids it forgot that cannot be rebuilt,
//! so the node can tell a publisher "forgotten, send it again" instead of a bare "unknown".
//!
//! Bat and ball ids are invented by publishers, so without a bound every new id would grow the node's memory
//! for ever. The capacity is small (tens to thousands), so finding the oldest entry by a linear scan, only
//! when the map is full, costs less than keeping an ordered index up to date on every swing.

use std::collections::{HashMap, HashSet, VecDeque};

/// Ids longer than this are not remembered once forgotten (the answer then just says "unknown"), so a
/// publisher inventing huge ids cannot make the memory of forgotten ids large.
const LONGEST_REMEMBERED_ID: usize = 256;

/// Forgotten ids remembered: at least this many (≤ 1 MB of ids), or the capacity if larger.
const FORGOTTEN_IDS_REMEMBERED: usize = 4096;

#[derive(Debug, Clone)]
struct Slot<V> {
    value: V,
    last_used: u64,
    rebuildable: bool,
}

/// At most `capacity` values by id, least recently used forgotten first.
#[derive(Debug, Clone)]
pub struct LruMap<V> {
    capacity: usize,
    entries: HashMap<String, Slot<V>>,
    clock: u64,
    forgotten_order: VecDeque<String>,
    forgotten: HashSet<String>,
    evictions: u64,
    last_evicted: Option<String>,
}

impl<V> LruMap<V> {
    /// Empty, keeping at most `capacity` (at least 1) entries.
    pub fn new(capacity: usize) -> LruMap<V> {
        LruMap {
            capacity: capacity.max(1),
            entries: HashMap::new(),
            clock: 0,
            forgotten_order: VecDeque::new(),
            forgotten: HashSet::new(),
            evictions: 0,
            last_evicted: None,
        }
    }

    /// Most entries kept.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Entries held now.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is held.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Entries forgotten to stay within the capacity, since creation.
    pub fn evictions(&self) -> u64 {
        self.evictions
    }

    /// The id forgotten most recently, if any.
    pub fn last_evicted(&self) -> Option<&str> {
        self.last_evicted.as_deref()
    }

    /// The value of `id`, marked as just used.
    pub fn get(&mut self, id: &str) -> Option<&V> {
        self.clock += 1;
        let now = self.clock;
        self.entries.get_mut(id).map(|slot| {
            slot.last_used = now;
            &slot.value
        })
    }

    /// The value of `id`, without marking it used.
    pub fn peek(&self, id: &str) -> Option<&V> {
        self.entries.get(id).map(|slot| &slot.value)
    }

    /// Whether `id` was forgotten (and not stored again since) although it could not be rebuilt.
    pub fn was_forgotten(&self, id: &str) -> bool {
        self.forgotten.contains(id)
    }

    /// Stores `value` under `id` as just used, first forgetting the least recently used entries other than
    /// `id` and `keep` until there is room. `rebuildable` entries (e.g. presets) are not remembered as
    /// forgotten: their owner makes them again on demand. Returns how many entries were forgotten.
    pub fn insert(&mut self, id: String, value: V, rebuildable: bool, keep: Option<&str>) -> usize {
        let mut evicted = 0;
        if !self.entries.contains_key(&id) {
            while self.entries.len() >= self.capacity && self.evict_oldest(&[id.as_str()], keep) {
                evicted += 1;
            }
        }
        self.unforget(&id);
        self.clock += 1;
        self.entries.insert(id, Slot { value, last_used: self.clock, rebuildable });
        evicted
    }

    /// Replaces the value of an entry held now, keeping its place in the use order. False if `id` is not held.
    pub fn replace(&mut self, id: &str, value: V) -> bool {
        match self.entries.get_mut(id) {
            Some(slot) => {
                slot.value = value;
                true
            }
            None => false,
        }
    }

    /// Changes the capacity (at least 1), forgetting the least recently used entries other than `keep` until
    /// the map fits. Returns how many were forgotten.
    pub fn set_capacity(&mut self, capacity: usize, keep: Option<&str>) -> usize {
        self.capacity = capacity.max(1);
        let mut evicted = 0;
        while self.entries.len() > self.capacity && self.evict_oldest(&[], keep) {
            evicted += 1;
        }
        self.trim_forgotten();
        evicted
    }

    /// Every (id, value) held, in no particular order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &V)> {
        self.entries.iter().map(|(id, slot)| (id.as_str(), &slot.value))
    }

    fn evict_oldest(&mut self, spare: &[&str], keep: Option<&str>) -> bool {
        let oldest = self
            .entries
            .iter()
            .filter(|(id, _)| !spare.contains(&id.as_str()) && Some(id.as_str()) != keep)
            .min_by_key(|(_, slot)| slot.last_used)
            .map(|(id, _)| id.clone());
        let Some(id) = oldest else { return false };
        let Some(slot) = self.entries.remove(&id) else { return false };
        self.evictions += 1;
        if !slot.rebuildable && id.len() <= LONGEST_REMEMBERED_ID {
            self.remember_forgotten(id.clone());
        }
        self.last_evicted = Some(id);
        true
    }

    fn remember_forgotten(&mut self, id: String) {
        if self.forgotten.insert(id.clone()) {
            self.forgotten_order.push_back(id);
        }
        self.trim_forgotten();
    }

    fn trim_forgotten(&mut self) {
        while self.forgotten_order.len() > self.capacity.max(FORGOTTEN_IDS_REMEMBERED) {
            if let Some(old) = self.forgotten_order.pop_front() {
                self.forgotten.remove(&old);
            }
        }
    }

    fn unforget(&mut self, id: &str) {
        if self.forgotten.remove(id) {
            self.forgotten_order.retain(|f| f != id);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_recently_used_goes_first_and_a_use_refreshes() {
        let mut m = LruMap::new(3);
        for id in ["a", "b", "c"] {
            assert_eq!(m.insert(id.into(), id.to_uppercase(), false, None), 0);
        }
        assert_eq!(m.get("a").map(String::as_str), Some("A")); // b is now the oldest
        assert_eq!(m.insert("d".into(), "D".into(), false, None), 1);
        assert!(m.peek("b").is_none() && m.was_forgotten("b") && m.last_evicted() == Some("b"));
        assert_eq!((m.len(), m.evictions()), (3, 1));
        // Storing a forgotten id again makes it known (and not "forgotten") again.
        m.insert("b".into(), "B2".into(), false, None);
        assert!(!m.was_forgotten("b") && m.peek("b").is_some());
        assert!(m.peek("c").is_none(), "c was the oldest then");
    }

    #[test]
    fn the_kept_id_survives_and_rebuildable_entries_are_not_remembered() {
        let mut m = LruMap::new(2);
        m.insert("latest".into(), 1, false, None);
        m.insert("preset".into(), 2, true, Some("latest"));
        m.insert("x".into(), 3, false, Some("latest"));
        assert!(m.peek("latest").is_some(), "the kept id is never forgotten, however old");
        assert!(m.peek("preset").is_none() && !m.was_forgotten("preset"));
        // Re-storing an id held now forgets nothing; replace keeps the use order.
        assert_eq!(m.insert("x".into(), 4, false, Some("latest")), 0);
        assert!(m.replace("x", 5) && !m.replace("gone", 6));
        assert_eq!(m.peek("x"), Some(&5));
    }

    #[test]
    fn memory_stays_bounded_however_many_ids_arrive() {
        let mut m = LruMap::new(8);
        for i in 0..10_000 {
            m.insert(format!("bat{i}"), i, false, None);
        }
        assert_eq!(m.len(), 8);
        assert_eq!(m.evictions(), 10_000 - 8);
        assert_eq!((m.forgotten.len(), m.forgotten_order.len()), (FORGOTTEN_IDS_REMEMBERED, FORGOTTEN_IDS_REMEMBERED));
        assert!(m.was_forgotten("bat9000") && !m.was_forgotten("bat0"), "the oldest forgotten ids fade out");
        let long = "x".repeat(LONGEST_REMEMBERED_ID + 1);
        m.insert(long.clone(), 0, false, None);
        for i in 0..8 {
            m.insert(format!("new{i}"), i, false, None);
        }
        assert!(!m.was_forgotten(&long));
        // Shrinking forgets down to the new capacity at once, sparing the kept id.
        assert_eq!(m.set_capacity(3, Some("new0")), 5);
        assert!(m.peek("new0").is_some() && m.len() == 3 && m.forgotten_order.len() <= FORGOTTEN_IDS_REMEMBERED);
    }
}
