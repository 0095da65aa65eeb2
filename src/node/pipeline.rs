//! Collisions off the DDS thread: a bounded queue, a pool of worker threads, and a sequencer that hands the
//! results on in the order the swings arrived.
//!
//! Memory is bounded by `capacity`: a swing holds a slot from [`Pipeline::submit`] until its result has been
//! delivered, so queued + computing + waiting-for-an-earlier-swing never exceeds it. When every slot is taken
//! the swing is refused (the caller counts and reports the drop) rather than queued.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError, Sender};

use super::engine::{compute, Computed, Plan};
use super::stats::NodeStats;

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
    /// The swing as received.
    pub payload: T,
}

/// Where results go, one at a time, in swing order (publishing and recording in the node; a Vec in tests).
pub trait ResultSink<T>: Send + 'static {
    /// Delivers one outcome. Returns false if it could not be sent (counted as a publish failure).
    fn deliver(&mut self, outcome: &Outcome<T>) -> bool;
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
        let sequencer = {
            let (in_flight, stats, stop) = (Arc::clone(&in_flight), Arc::clone(&stats), Arc::clone(&stop));
            std::thread::Builder::new()
                .name("sweetspot-sequencer".into())
                .spawn(move || sequencer_loop(done_rx, sink, &in_flight, &stats, &stop))?
        };
        Ok(Pipeline {
            jobs: Some(job_tx),
            in_flight,
            capacity,
            next_seq: AtomicU64::new(0),
            stop,
            workers: handles,
            sequencer: Some(sequencer),
        })
    }

    /// Queues a swing. `Err` gives it back when `capacity` swings are already in flight (a drop).
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
    /// rest (they are in the bag as inputs) and returns once every thread has ended.
    pub fn shutdown(mut self, drain: Duration) {
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
        let result = compute(&job.plan, stats);
        let outcome = Outcome {
            seq: job.seq,
            received: job.received,
            bat_id: job.plan.bat_id().to_string(),
            ball_id: job.plan.ball_id().to_string(),
            result,
            payload: job.payload,
        };
        if done.send(outcome).is_err() {
            return;
        }
    }
}

fn sequencer_loop<T>(
    done: Receiver<Outcome<T>>,
    mut sink: impl ResultSink<T>,
    in_flight: &AtomicUsize,
    stats: &NodeStats,
    stop: &AtomicBool,
) {
    let mut waiting: BTreeMap<u64, Outcome<T>> = BTreeMap::new();
    let mut next = 0u64;
    // Ends when every worker has ended (all senders dropped), or at once when stopped: what is left is
    // abandoned (the swings are in the bag as inputs).
    for outcome in done.iter() {
        waiting.insert(outcome.seq, outcome);
        while let Some(outcome) = waiting.remove(&next) {
            if stop.load(Ordering::Acquire) {
                return;
            }
            let delivered = sink.deliver(&outcome);
            match (&outcome.result, delivered) {
                (_, false) => NodeStats::bump(&stats.publish_failures),
                (Ok(_), true) => NodeStats::bump(&stats.swings_ok),
                (Err(_), true) => NodeStats::bump(&stats.swings_rejected),
            }
            stats.record_latency(outcome.received.elapsed());
            in_flight.fetch_sub(1, Ordering::AcqRel);
            next += 1;
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
}
