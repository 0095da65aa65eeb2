//! Collisions off the DDS thread: a bounded queue, a pool of worker threads, and a sequencer that hands the
//! results on in the order the swings arrived.
//!
//! Memory is bounded by `capacity`: a swing holds a slot from [`Pipeline::submit`] until its result has been
//! delivered, so queued + computing + waiting-for-an-earlier-swing never exceeds it. When every slot is taken
//! the swing is refused (the caller counts and reports the drop) rather than queued.
//!
//! When nothing is in flight, [`Pipeline::answer_inline`] computes and delivers a cheap swing (its bat's modes
//! already solved, or a rejection) on the caller's thread: order is trivially kept, and the answer skips two
//! thread wake-ups (worker, sequencer). The sink sits behind a mutex both paths take; it is uncontended,
//! since the sequencer has nothing to deliver while nothing is in flight. [`InlinePacing`] keeps a burst from
//! being served one swing at a time on the receive thread.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError, Sender};

use super::stats::NodeStats;
use crate::model::engine::{compute, BatEntry, Computed, Plan};

/// One swing on its way through the pipeline; `payload` is carried along untouched (the swing message).
#[derive(Debug)]
pub struct Job<T> {
    /// Position in arrival order.
    pub seq: u64,
    /// When the swing was taken from DDS (for the latency histogram).
    pub received: Instant,
    /// What to compute.
    pub plan: Plan,
    /// The swing as received.
    pub payload: T,
}

/// A finished swing, delivered in arrival order.
#[derive(Debug)]
pub struct Outcome<T> {
    /// Position in arrival order.
    pub seq: u64,
    /// When the swing was taken from DDS.
    pub received: Instant,
    /// Resolved bat_id.
    pub bat_id: String,
    /// Resolved ball_id.
    pub ball_id: String,
    /// The result, or why the swing was rejected.
    pub result: Result<Computed, String>,
    /// The bat (with its solved modes) and the ball's radius, m, of a computed swing: what its scene is
    /// drawn from ([`crate::model::scene`]); `None` for a rejection.
    pub drawn_from: Option<(Arc<BatEntry>, f64)>,
    /// The swing as received.
    pub payload: T,
}

/// Where results go, one at a time, in swing order (publishing and recording in the node; a Vec in tests).
pub trait ResultSink<T>: Send + 'static {
    /// Delivers one outcome. Returns false if it could not be sent (counted as a publish failure).
    fn deliver(&mut self, outcome: &Outcome<T>) -> bool;
}

/// The sink and the next sequence number it is owed, taken together by whichever thread delivers.
struct Delivery<T> {
    sink: Box<dyn ResultSink<T>>,
    next: u64,
}

/// The running pipeline.
pub struct Pipeline<T> {
    jobs: Option<Sender<Job<T>>>,
    in_flight: Arc<AtomicUsize>,
    capacity: usize,
    next_seq: AtomicU64,
    stop: Arc<AtomicBool>,
    workers: Vec<JoinHandle<()>>,
    sequencer: Option<JoinHandle<()>>,
    delivery: Arc<Mutex<Delivery<T>>>,
    stats: Arc<NodeStats>,
}

impl<T: Send + 'static> Pipeline<T> {
    /// Starts `workers` threads and the sequencer feeding `sink`.
    pub fn start(
        workers: usize,
        capacity: usize,
        stats: Arc<NodeStats>,
        sink: impl ResultSink<T>,
    ) -> std::io::Result<Pipeline<T>> {
        let capacity = capacity.max(1);
        let (job_tx, job_rx) = crossbeam_channel::bounded::<Job<T>>(capacity);
        // Bounded by `capacity` through the in-flight slots, so an unbounded channel cannot grow past it.
        let (done_tx, done_rx) = crossbeam_channel::unbounded::<Outcome<T>>();
        let in_flight = Arc::new(AtomicUsize::new(0));
        let stop = Arc::new(AtomicBool::new(false));
        let mut handles = Vec::new();
        for i in 0..workers.max(1) {
            let (rx, tx, stats, stop) = (job_rx.clone(), done_tx.clone(), Arc::clone(&stats), Arc::clone(&stop));
            handles.push(
                std::thread::Builder::new()
                    .name(format!("sweetspot-worker-{i}"))
                    .spawn(move || worker_loop(rx, tx, &stats, &stop))?,
            );
        }
        drop(done_tx);
        let delivery = Arc::new(Mutex::new(Delivery { sink: Box::new(sink) as Box<dyn ResultSink<T>>, next: 0 }));
        let sequencer = {
            let (in_flight, stats, stop) = (Arc::clone(&in_flight), Arc::clone(&stats), Arc::clone(&stop));
            let delivery = Arc::clone(&delivery);
            std::thread::Builder::new()
                .name("sweetspot-sequencer".into())
                .spawn(move || sequencer_loop(done_rx, &delivery, &in_flight, &stats, &stop))?
        };
        Ok(Pipeline {
            jobs: Some(job_tx),
            in_flight,
            capacity,
            next_seq: AtomicU64::new(0),
            stop,
            workers: handles,
            sequencer: Some(sequencer),
            delivery,
            stats,
        })
    }

    /// Computes and delivers a swing on the calling thread when nothing is in flight (so every earlier swing
    /// has been delivered) and `plan` is cheap (a rejection, or a bat whose modes are solved: one collision,
    /// never a modes solve). `Err` gives the swing back untouched otherwise; the caller then [`submit`]s it.
    /// Counters, the latency histogram and sequence numbers are kept exactly as for a queued swing.
    ///
    /// [`submit`]: Pipeline::submit
    #[allow(clippy::result_large_err)] // `Err` hands the swing back by value, once; no error travels far
    pub fn answer_inline(&self, received: Instant, plan: Plan, payload: T) -> Result<u64, (Plan, T)> {
        let cheap = match &plan {
            Plan::Reject { .. } => true,
            Plan::Collide { bat, .. } => bat.modes_cached(),
        };
        // Only the node's receive task submits or answers, so nothing can enter between check and claim.
        if self.jobs.is_none() || !cheap || self.in_flight.load(Ordering::Acquire) != 0 {
            return Err((plan, payload));
        }
        self.in_flight.fetch_add(1, Ordering::AcqRel);
        let seq = self.next_seq.fetch_add(1, Ordering::Relaxed);
        let outcome = run_job(Job { seq, received, plan, payload }, &self.stats);
        let mut delivery = match self.delivery.lock() {
            Ok(delivery) => delivery,
            Err(poisoned) => poisoned.into_inner(),
        };
        debug_assert_eq!(delivery.next, seq, "nothing was in flight, so this swing is the next one owed");
        deliver_next(&mut delivery, &outcome, &self.in_flight, &self.stats);
        NodeStats::bump(&self.stats.swings_answered_inline);
        Ok(seq)
    }

    /// Queues a swing. `Err` gives it back when `capacity` swings are already in flight (a drop).
    #[allow(clippy::result_large_err)] // `Err` hands the swing back by value, once; no error travels far
    pub fn submit(&self, received: Instant, plan: Plan, payload: T) -> Result<u64, (Plan, T)> {
        let Some(jobs) = &self.jobs else { return Err((plan, payload)) };
        // Only the node's receive task submits, so check-then-increment cannot overshoot.
        if self.in_flight.load(Ordering::Acquire) >= self.capacity {
            return Err((plan, payload));
        }
        self.in_flight.fetch_add(1, Ordering::AcqRel);
        let seq = self.next_seq.fetch_add(1, Ordering::Relaxed);
        match jobs.try_send(Job { seq, received, plan, payload }) {
            Ok(()) => Ok(seq),
            Err(err) => {
                // Unreachable while the slot accounting holds; keep the sequence gap-free anyway.
                self.in_flight.fetch_sub(1, Ordering::AcqRel);
                self.next_seq.fetch_sub(1, Ordering::Relaxed);
                let job = err.into_inner();
                Err((job.plan, job.payload))
            }
        }
    }

    /// Swings queued, computing, or waiting for an earlier one.
    pub fn in_flight(&self) -> u64 {
        self.in_flight.load(Ordering::Acquire) as u64
    }

    /// Maximum swings in flight.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Stops taking swings, lets the workers finish what is queued for at most `drain`, then abandons the
    /// rest (they are in the bag as inputs) and returns, once every thread has ended, how many swings were
    /// abandoned (never answered).
    pub fn shutdown(mut self, drain: Duration) -> u64 {
        self.jobs = None; // closing the queue lets idle workers exit
        let deadline = Instant::now() + drain;
        while self.in_flight() > 0 && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        self.stop.store(true, Ordering::Release);
        for handle in self.workers.drain(..) {
            let _ = handle.join();
        }
        if let Some(handle) = self.sequencer.take() {
            let _ = handle.join();
        }
        // Every thread has ended: no slot is freed any more.
        self.in_flight()
    }
}

impl<T> Drop for Pipeline<T> {
    fn drop(&mut self) {
        self.jobs = None;
        self.stop.store(true, Ordering::Release);
    }
}

fn worker_loop<T>(jobs: Receiver<Job<T>>, done: Sender<Outcome<T>>, stats: &NodeStats, stop: &AtomicBool) {
    loop {
        if stop.load(Ordering::Acquire) {
            return;
        }
        let job = match jobs.recv_timeout(Duration::from_millis(50)) {
            Ok(job) => job,
            Err(RecvTimeoutError::Timeout) => continue,
            Err(RecvTimeoutError::Disconnected) => return,
        };
        if done.send(run_job(job, stats)).is_err() {
            return;
        }
    }
}

fn run_job<T>(job: Job<T>, stats: &NodeStats) -> Outcome<T> {
    let result = compute(&job.plan, stats);
    Outcome {
        seq: job.seq,
        received: job.received,
        bat_id: job.plan.bat_id().to_string(),
        ball_id: job.plan.ball_id().to_string(),
        result,
        drawn_from: match &job.plan {
            Plan::Collide { bat, ball, .. } => Some((Arc::clone(bat), ball.radius)),
            Plan::Reject { .. } => None,
        },
        payload: job.payload,
    }
}

/// Hands `outcome` (the one `delivery` is owed) to the sink, counts it and frees its slot.
fn deliver_next<T: 'static>(
    delivery: &mut Delivery<T>,
    outcome: &Outcome<T>,
    in_flight: &AtomicUsize,
    stats: &NodeStats,
) {
    let delivered = delivery.sink.deliver(outcome);
    match (&outcome.result, delivered) {
        (_, false) => NodeStats::bump(&stats.publish_failures),
        (Ok(_), true) => NodeStats::bump(&stats.swings_ok),
        (Err(_), true) => NodeStats::bump(&stats.swings_rejected),
    }
    stats.record_latency(outcome.received.elapsed());
    // `next` moves on before the slot is freed: whoever sees nothing in flight sees every delivery done.
    delivery.next += 1;
    in_flight.fetch_sub(1, Ordering::AcqRel);
}

fn sequencer_loop<T: 'static>(
    done: Receiver<Outcome<T>>,
    delivery: &Mutex<Delivery<T>>,
    in_flight: &AtomicUsize,
    stats: &NodeStats,
    stop: &AtomicBool,
) {
    let mut waiting: BTreeMap<u64, Outcome<T>> = BTreeMap::new();
    // Ends when every worker has ended (all senders dropped), or at once when stopped: what is left is
    // abandoned (the swings are in the bag as inputs).
    for outcome in done.iter() {
        waiting.insert(outcome.seq, outcome);
        let mut delivery = match delivery.lock() {
            Ok(delivery) => delivery,
            Err(poisoned) => poisoned.into_inner(),
        };
        while let Some(outcome) = waiting.remove(&delivery.next) {
            if stop.load(Ordering::Acquire) {
                return;
            }
            deliver_next(&mut delivery, &outcome, in_flight, stats);
        }
    }
}

/// Decides whether the receive thread may answer the next swing itself: as long as inline answers take at
/// most half its time, with bursts of up to [`InlinePacing::BURST`] of inline work allowed beyond that. A
/// short burst of swings (a client's timer firing late sends several back to back) is then answered inline
/// one after another, each waiting a few tens of µs for the ones ahead instead of paying the worker and
/// sequencer wake-ups; a rate the receive thread cannot keep up with alone runs the budget dry and goes to
/// the workers, which compute in parallel.
#[derive(Debug, Clone, Default)]
pub struct InlinePacing {
    /// Inline work beyond half the elapsed time, as of `settled`.
    debt: Duration,
    settled: Option<Instant>,
}

impl InlinePacing {
    /// Inline work the receive thread may run ahead of its half share.
    pub const BURST: Duration = Duration::from_micros(200);

    /// A pacing with its whole burst available.
    pub fn new() -> InlinePacing {
        InlinePacing::default()
    }

    /// Whether a swing taken at `now` may be answered inline.
    pub fn allows(&self, now: Instant) -> bool {
        self.debt_at(now) < Self::BURST
    }

    /// Notes an inline answer that ran from `started` to `ended`.
    pub fn answered(&mut self, started: Instant, ended: Instant) {
        self.debt = self.debt_at(ended) + ended.saturating_duration_since(started);
        self.settled = Some(ended);
    }

    fn debt_at(&self, now: Instant) -> Duration {
        match self.settled {
            None => Duration::ZERO,
            // Half of every elapsed moment is the receive thread's to spend inline.
            Some(settled) => self.debt.saturating_sub(now.saturating_duration_since(settled) / 2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    struct VecSink(Arc<Mutex<Vec<(u64, u32, bool)>>>);

    impl ResultSink<u32> for VecSink {
        fn deliver(&mut self, o: &Outcome<u32>) -> bool {
            self.0.lock().unwrap().push((o.seq, o.payload, o.result.is_ok()));
            true
        }
    }

    fn reject(i: u32) -> Plan {
        Plan::Reject { bat_id: format!("bat{i}"), ball_id: "baseball".into(), reason: format!("reason {i}") }
    }

    #[test]
    fn results_come_out_in_submission_order_from_many_workers() {
        let out = Arc::new(Mutex::new(Vec::new()));
        let stats = Arc::new(NodeStats::new());
        let p = Pipeline::start(4, 10_000, Arc::clone(&stats), VecSink(Arc::clone(&out))).unwrap();
        for i in 0..5_000u32 {
            p.submit(Instant::now(), reject(i), i).unwrap();
        }
        p.shutdown(Duration::from_secs(30));
        let out = out.lock().unwrap();
        assert_eq!(out.len(), 5_000);
        for (k, (seq, payload, ok)) in out.iter().enumerate() {
            assert_eq!((*seq, *payload, *ok), (k as u64, k as u32, false));
        }
        assert_eq!(stats.snapshot(0).swings_rejected, 5_000);
    }

    struct SlowSink(Arc<Mutex<Vec<u32>>>, Arc<AtomicBool>);

    impl ResultSink<u32> for SlowSink {
        fn deliver(&mut self, o: &Outcome<u32>) -> bool {
            while !self.1.load(Ordering::Acquire) {
                std::thread::sleep(Duration::from_millis(1));
            }
            self.0.lock().unwrap().push(o.payload);
            true
        }
    }

    #[test]
    fn a_full_pipeline_refuses_instead_of_growing() {
        let out = Arc::new(Mutex::new(Vec::new()));
        let release = Arc::new(AtomicBool::new(false));
        let stats = Arc::new(NodeStats::new());
        let p = Pipeline::start(2, 8, stats, SlowSink(Arc::clone(&out), Arc::clone(&release))).unwrap();
        let mut accepted = 0;
        let mut refused = 0;
        for i in 0..100u32 {
            match p.submit(Instant::now(), reject(i), i) {
                Ok(_) => accepted += 1,
                Err((_, payload)) => {
                    assert_eq!(payload, i);
                    refused += 1
                }
            }
            assert!(p.in_flight() <= 8);
        }
        assert_eq!((accepted, refused), (8, 92));
        release.store(true, Ordering::Release);
        p.shutdown(Duration::from_secs(30));
        assert_eq!(*out.lock().unwrap(), (0..8).collect::<Vec<u32>>());
    }

    /// Fails every third delivery, and holds deliveries while `hold` is set.
    struct FlakySink(Arc<AtomicBool>);

    impl ResultSink<u32> for FlakySink {
        fn deliver(&mut self, o: &Outcome<u32>) -> bool {
            while self.0.load(Ordering::Acquire) {
                std::thread::sleep(Duration::from_millis(1));
            }
            !o.payload.is_multiple_of(3)
        }
    }

    /// The node's summary line adds these up: every swing submitted is answered (OK or REJECTED), unsent
    /// (publish failed), refused (dropped), or reported by `shutdown` as still queued.
    #[test]
    fn every_swing_is_accounted_for_once_failed_publishes_and_swings_abandoned_at_shutdown_included() {
        let hold = Arc::new(AtomicBool::new(false));
        let stats = Arc::new(NodeStats::new());
        let p = Pipeline::start(2, 16, Arc::clone(&stats), FlakySink(Arc::clone(&hold))).unwrap();
        let mut dropped = 0u64;
        for i in 0..30u32 {
            if p.submit(Instant::now(), reject(i), i).is_err() {
                dropped += 1;
            }
            wait_until_idle(&p);
        }
        // Now the sink stalls: 16 swings fill the queue, 4 more are refused, and shutdown gives up on the 16.
        hold.store(true, Ordering::Release);
        for i in 30..50u32 {
            if p.submit(Instant::now(), reject(i), i).is_err() {
                dropped += 1;
            }
        }
        let releaser = {
            let hold = Arc::clone(&hold);
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_millis(300));
                hold.store(false, Ordering::Release);
            })
        };
        let abandoned = p.shutdown(Duration::from_millis(50));
        releaser.join().unwrap();
        let s = stats.snapshot(abandoned);
        assert_eq!(dropped, 4);
        // The stalled sink holds one swing when shutdown stops waiting; it may still finish it (swing 30, whose
        // publish fails), the rest stay queued.
        assert!((15..=16).contains(&abandoned), "{abandoned} abandoned");
        // 0..30 delivered: the 10 multiples of 3 failed to publish.
        assert_eq!((s.swings_ok, s.swings_rejected, s.publish_failures), (0, 20, 10 + (16 - abandoned)));
        assert_eq!(s.swings_ok + s.swings_rejected + s.publish_failures + dropped + abandoned, 50);
    }

    fn wait_until_idle<T: Send + 'static>(p: &Pipeline<T>) {
        while p.in_flight() > 0 {
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    #[test]
    fn inline_and_queued_answers_interleave_in_order_with_every_counter_right() {
        let out = Arc::new(Mutex::new(Vec::new()));
        let stats = Arc::new(NodeStats::new());
        let p = Pipeline::start(2, 64, Arc::clone(&stats), VecSink(Arc::clone(&out))).unwrap();
        let (mut inline, mut queued) = (0u64, 0u64);
        for i in 0..3_000u32 {
            if i % 5 == 0 {
                // Idle, so the inline path must take it, with the next sequence number.
                wait_until_idle(&p);
                assert_eq!(p.answer_inline(Instant::now(), reject(i), i).ok(), Some(u64::from(i)));
                assert_eq!(p.in_flight(), 0, "an inline answer frees its slot before returning");
                inline += 1;
            } else if i % 5 == 4 {
                // Right after three queued swings: inline only if they are all delivered already, else
                // refused, and the swing, given back untouched, is queued behind them.
                match p.answer_inline(Instant::now(), reject(i), i) {
                    Ok(seq) => {
                        assert_eq!(seq, u64::from(i));
                        inline += 1;
                    }
                    Err((plan, payload)) => {
                        assert_eq!(payload, i);
                        assert_eq!(plan.bat_id(), format!("bat{i}"));
                        assert_eq!(p.submit(Instant::now(), plan, payload).ok(), Some(u64::from(i)));
                        queued += 1;
                    }
                }
            } else {
                assert_eq!(p.submit(Instant::now(), reject(i), i).ok(), Some(u64::from(i)));
                queued += 1;
            }
        }
        p.shutdown(Duration::from_secs(30));
        let out = out.lock().unwrap();
        assert_eq!(out.len(), 3_000);
        for (k, (seq, payload, ok)) in out.iter().enumerate() {
            assert_eq!((*seq, *payload, *ok), (k as u64, k as u32, false), "delivered in arrival order");
        }
        assert!(inline >= 600 && queued >= 1_800 && inline + queued == 3_000, "inline {inline}, queued {queued}");
        let snap = stats.snapshot(0);
        assert_eq!((snap.swings_rejected, snap.swings_ok, snap.publish_failures), (3_000, 0, 0));
        assert_eq!(stats.latency_count(), 3_000, "one latency per swing, whichever path answered it");
        assert_eq!(snap.swings_answered_inline, inline);
    }

    #[test]
    fn inline_is_refused_while_anything_is_in_flight_and_the_queue_keeps_order() {
        let out = Arc::new(Mutex::new(Vec::new()));
        let release = Arc::new(AtomicBool::new(false));
        let stats = Arc::new(NodeStats::new());
        let p = Pipeline::start(2, 8, Arc::clone(&stats), SlowSink(Arc::clone(&out), Arc::clone(&release))).unwrap();
        assert_eq!(p.submit(Instant::now(), reject(0), 0).ok(), Some(0));
        // Swing 0 is held in the sink: answering 1 inline would overtake it.
        let (plan, payload) = p.answer_inline(Instant::now(), reject(1), 1).unwrap_err();
        assert_eq!(payload, 1);
        assert_eq!(p.submit(Instant::now(), plan, payload).ok(), Some(1));
        assert_eq!(p.in_flight(), 2);
        release.store(true, Ordering::Release);
        wait_until_idle(&p);
        assert_eq!(p.answer_inline(Instant::now(), reject(2), 2).ok(), Some(2));
        assert_eq!(p.submit(Instant::now(), reject(3), 3).ok(), Some(3));
        p.shutdown(Duration::from_secs(30));
        assert_eq!(*out.lock().unwrap(), vec![0, 1, 2, 3]);
        assert_eq!(stats.snapshot(0).swings_rejected, 4);
        assert_eq!(stats.snapshot(0).swings_answered_inline, 1);
        assert_eq!(stats.latency_count(), 4);
    }

    #[test]
    fn inline_takes_a_collision_only_once_its_bat_has_modes() {
        use crate::model::engine::BatEntry;
        use crate::model::settings::ModelSettings;
        use crate::physics::{Ball, Bat, CollisionOptions, Impact};
        let out = Arc::new(Mutex::new(Vec::new()));
        let stats = Arc::new(NodeStats::new());
        let p = Pipeline::start(1, 8, Arc::clone(&stats), VecSink(Arc::clone(&out))).unwrap();
        let bat = Arc::new(BatEntry::new("r161", Bat::preset("r161").unwrap(), Some(6), &ModelSettings::default()));
        let collide = || Plan::Collide {
            bat: Arc::clone(&bat),
            ball_id: "baseball".into(),
            ball: Ball::default(),
            contact: Default::default(),
            impact: Impact { ball_speed: 40.0, bat_cm_speed: 20.0, bat_angular_speed: 50.0, impact_z: 0.6 },
            oblique: None,
            options: CollisionOptions { modes: 6, ..CollisionOptions::default() },
        };
        // Modes not solved yet: a solve takes milliseconds, so it goes to a worker.
        let (plan, payload) = p.answer_inline(Instant::now(), collide(), 0).unwrap_err();
        assert_eq!(p.submit(Instant::now(), plan, payload).ok(), Some(0));
        wait_until_idle(&p);
        assert!(bat.modes_cached());
        assert_eq!(p.answer_inline(Instant::now(), collide(), 1).ok(), Some(1));
        p.shutdown(Duration::from_secs(30));
        assert_eq!(*out.lock().unwrap(), vec![(0, 0, true), (1, 1, true)]);
        let snap = stats.snapshot(0);
        assert_eq!((snap.swings_ok, snap.mode_cache_misses, snap.mode_cache_hits), (2, 1, 1));
    }

    #[test]
    fn inline_pacing_allows_a_short_burst_and_half_the_time_beyond_it() {
        let t0 = Instant::now();
        let us = Duration::from_micros;
        let mut pacing = InlinePacing::new();
        assert!(pacing.allows(t0), "the first swing");
        // Back-to-back answers of 20 µs: each adds 20 µs of work and earns 10 µs (the first earns nothing),
        // so the 200 µs burst is spent after 19 of them.
        let mut now = t0;
        let mut answered = 0;
        while pacing.allows(now) {
            pacing.answered(now, now + us(20));
            now += us(20);
            answered += 1;
        }
        assert_eq!(answered, 19);
        // Idle time pays it back at half speed.
        assert!(!pacing.allows(now));
        assert!(pacing.allows(now + us(2)), "2 µs idle bring the debt below the burst");
        assert!(pacing.allows(now + us(400)));
        // A steady 20 µs answer every 50 µs (40 % of the time) never runs out.
        let mut pacing = InlinePacing::new();
        for k in 0..10_000u32 {
            let at = t0 + us(50) * k;
            assert!(pacing.allows(at), "refused at swing {k}");
            pacing.answered(at, at + us(20));
        }
        // Every 30 µs (67 %) does, and then stays refused about a third of the time.
        let mut pacing = InlinePacing::new();
        let refused = (0..10_000u32)
            .filter(|&k| {
                let at = t0 + us(30) * k;
                let allowed = pacing.allows(at);
                if allowed {
                    pacing.answered(at, at + us(20));
                }
                !allowed
            })
            .count();
        assert!((2_000..=3_500).contains(&refused), "{refused} of 10000 refused");
    }
}
