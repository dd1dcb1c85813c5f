//! A persistent team of threads for the time step's parallel loops.
//!
//! A step runs four parallel sections (positions, two colours of element blocks, the free velocity)
//! separated by short serial stages. Through rayon each section paid for waking a pool thread that
//! had gone to sleep during the serial stages, and its work stealing handed the halves of the nodal
//! arrays to the two cores at random, so each section found half of its data in the other core's
//! L2. `decohesion bench` measured both (docs: performance log).
//!
//! The team keeps its threads spinning for [`SPIN`] after each section, so within a run a
//! section starts in well under a microsecond, and gives every participant a fixed, contiguous
//! share of each loop ([`Team::map`]): thread t always works on the same part of the nodal
//! arrays and keeps it in its own core's cache. After [`SPIN`] without work the threads park
//! (an idle simulation costs no CPU); after [`YIELD`] of spinning they yield to any other thread
//! the machine needs to run.
//!
//! Results never depend on the team size: a loop item is computed the same way by whichever
//! thread runs it, and [`Team::map`] returns the items in index order for fixed-order
//! reductions.

use crossbeam_utils::sync::{Parker, Unparker};
use crossbeam_utils::CachePadded;
use std::any::Any;
use std::cell::UnsafeCell;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long an idle thread spins (then yields) before it parks.
const SPIN: Duration = Duration::from_millis(2);
/// How long it busy-spins before it starts yielding the core at each check.
const YIELD: Duration = Duration::from_micros(100);

/// The job of the current section, seen by the workers.
type Job = *const (dyn Fn(usize) + Sync + 'static);

struct Shared {
    /// Bumped (Release) once the job is in place; a worker runs each new epoch once.
    epoch: AtomicU64,
    job: UnsafeCell<Option<Job>>,
    /// Workers still running the current job.
    running: AtomicUsize,
    stop: AtomicBool,
    /// A job is in progress (see [`Team::run`] for calls made meanwhile).
    busy: AtomicBool,
    panic: Mutex<Option<Box<dyn Any + Send>>>,
}

// SAFETY: `job` is written by the caller only while no worker runs (running == 0, read with
// Acquire) and read by the workers only after they see the new epoch (Acquire after the
// caller's Release), so the accesses never overlap.
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

/// A fixed set of `size` participants: the calling thread (index 0) and `size − 1` workers.
pub struct Team {
    shared: Arc<Shared>,
    /// Next unclaimed item of each participant's share in [`Team::map`].
    next: Vec<CachePadded<AtomicUsize>>,
    unparkers: Vec<Unparker>,
    workers: Vec<JoinHandle<()>>,
}

impl Team {
    /// A team of `size` participants (at least 1); spawns `size − 1` threads.
    pub fn new(size: usize) -> Team {
        let shared = Arc::new(Shared {
            epoch: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            running: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
            busy: AtomicBool::new(false),
            panic: Mutex::new(None),
        });
        let mut unparkers = Vec::new();
        let mut workers = Vec::new();
        for index in 1..size.max(1) {
            let parker = Parker::new();
            unparkers.push(parker.unparker().clone());
            let shared = Arc::clone(&shared);
            let handle = std::thread::Builder::new()
                .name(format!("decohesion-team-{index}"))
                .spawn(move || worker(&shared, &parker, index))
                .expect("cannot spawn a worker thread");
            workers.push(handle);
        }
        Team {
            shared,
            next: (0..size.max(1))
                .map(|_| CachePadded::new(AtomicUsize::new(0)))
                .collect(),
            unparkers,
            workers,
        }
    }

    /// Number of participants, the caller included.
    pub fn size(&self) -> usize {
        self.workers.len() + 1
    }

    /// Runs `f(t)` once on every participant t (the caller runs t = 0) and returns when all
    /// have finished. A panic in any of them is re-raised here, after all have finished.
    ///
    /// A call made while the team is busy (from inside one of its jobs, or from another thread)
    /// runs f(0), f(1), … on the calling thread instead: same work, no deadlock, no race.
    pub fn run(&self, f: &(dyn Fn(usize) + Sync)) {
        match self.claim() {
            Some(_busy) => self.run_claimed(f),
            None => (0..self.size()).for_each(f),
        }
    }

    /// Marks the team busy until the guard drops; None if it already is.
    fn claim(&self) -> Option<Busy<'_>> {
        // `then`, not `then_some`: a guard built for a failed claim would release the holder's.
        (!self.shared.busy.swap(true, Ordering::Acquire)).then(|| Busy(&self.shared.busy))
    }

    fn run_claimed(&self, f: &(dyn Fn(usize) + Sync)) {
        if self.workers.is_empty() {
            f(0);
            return;
        }
        let sh = &*self.shared;
        // SAFETY: the job only lives until this function returns, and it returns only once no
        // worker runs it any more (running == 0 below, also on a panic).
        let job: Job = unsafe { std::mem::transmute::<&(dyn Fn(usize) + Sync), Job>(f) };
        unsafe { *sh.job.get() = Some(job) };
        sh.running.store(self.workers.len(), Ordering::Relaxed);
        sh.epoch.fetch_add(1, Ordering::Release);
        for u in &self.unparkers {
            u.unpark();
        }
        let mine = catch_unwind(AssertUnwindSafe(|| f(0)));
        let start = Instant::now();
        let mut spins = 0u32;
        while sh.running.load(Ordering::Acquire) != 0 {
            spins = spins.wrapping_add(1);
            if spins.is_multiple_of(64) && start.elapsed() > YIELD {
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
        if let Err(p) = mine {
            resume_unwind(p);
        }
        if let Some(p) = sh.panic.lock().map(|mut g| g.take()).unwrap_or(None) {
            resume_unwind(p);
        }
    }

    /// `f(i)` for every i in 0..n; the results in index order (allocates the result; see
    /// [`Team::map_into`]).
    ///
    /// Participant t works through its contiguous share [t·n/T, (t+1)·n/T) first, so it keeps
    /// touching the same part of the data from one call to the next; once done it takes the
    /// items still unclaimed in the other shares, so a thread the machine slows down (another
    /// process, a hypervisor) delays the section by at most about one item.
    pub fn map<R: Send>(&self, n: usize, f: impl Fn(usize) -> R + Sync) -> Vec<R> {
        let mut out = Vec::new();
        self.map_into(n, &mut out, f);
        out
    }

    /// [`Team::map`] into `out` (cleared first), reusing its capacity: a step that keeps its
    /// result buffers allocates nothing.
    pub fn map_into<R: Send>(&self, n: usize, out: &mut Vec<R>, f: impl Fn(usize) -> R + Sync) {
        out.clear();
        let Some(_busy) = self.claim() else {
            out.extend((0..n).map(f));
            return;
        };
        out.reserve(n);
        let slots = SharedSlice {
            ptr: out.as_mut_ptr(),
            len: n,
        };
        let size = self.size();
        for (t, next) in self.next.iter().enumerate() {
            next.store(share(n, t, size).start, Ordering::Relaxed);
        }
        // SAFETY: every index is claimed once (fetch_add on its share's counter), so every slot
        // is written by one participant only; `run` publishes the counters (Release) and
        // returns after all writes (Acquire). A panic leaves `out` empty (written items leak,
        // none is dropped twice).
        self.run_claimed(&|t| {
            for k in 0..size {
                let owner = (t + k) % size;
                let end = share(n, owner, size).end;
                loop {
                    let i = self.next[owner].fetch_add(1, Ordering::Relaxed);
                    if i >= end {
                        break;
                    }
                    unsafe { slots.as_ptr().add(i).write(f(i)) };
                }
            }
        });
        unsafe { out.set_len(n) };
    }
}

/// Holds a team busy; releases it when dropped (also on a panic).
struct Busy<'a>(&'a AtomicBool);

impl Drop for Busy<'_> {
    fn drop(&mut self) {
        self.0.store(false, Ordering::Release);
    }
}

/// Participant t's share of n items among `size`: [t·n/size, (t+1)·n/size).
pub fn share(n: usize, t: usize, size: usize) -> std::ops::Range<usize> {
    t * n / size..(t + 1) * n / size
}

impl Drop for Team {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        self.shared.epoch.fetch_add(1, Ordering::Release);
        for u in &self.unparkers {
            u.unpark();
        }
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
    }
}

fn worker(sh: &Shared, parker: &Parker, index: usize) {
    let mut seen = 0u64;
    loop {
        let start = Instant::now();
        let mut spins = 0u32;
        loop {
            let e = sh.epoch.load(Ordering::Acquire);
            if e != seen {
                seen = e;
                break;
            }
            spins = spins.wrapping_add(1);
            if spins.is_multiple_of(64) {
                let idle = start.elapsed();
                if idle > SPIN {
                    parker.park_timeout(Duration::from_millis(100));
                } else if idle > YIELD {
                    std::thread::yield_now();
                }
            } else {
                std::hint::spin_loop();
            }
        }
        if sh.stop.load(Ordering::Acquire) {
            return;
        }
        // SAFETY: the epoch was read with Acquire after the caller set the job (Release).
        if let Some(job) = unsafe { *sh.job.get() } {
            let r = catch_unwind(AssertUnwindSafe(|| unsafe { (*job)(index) }));
            if let Err(p) = r {
                if let Ok(mut g) = sh.panic.lock() {
                    g.get_or_insert(p);
                }
            }
        }
        sh.running.fetch_sub(1, Ordering::Release);
    }
}

/// A mutable slice handed to the participants of a team, each taking its own disjoint parts.
pub struct SharedSlice<T> {
    ptr: *mut T,
    len: usize,
}

// Copy whatever T is (a derive would ask T: Copy).
impl<T> Clone for SharedSlice<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for SharedSlice<T> {}

// SAFETY: the users of a SharedSlice only ever create references to disjoint parts.
unsafe impl<T: Send> Send for SharedSlice<T> {}
unsafe impl<T: Send> Sync for SharedSlice<T> {}

impl<T> SharedSlice<T> {
    pub fn new(s: &mut [T]) -> Self {
        SharedSlice {
            ptr: s.as_mut_ptr(),
            len: s.len(),
        }
    }

    /// Items [a, b) (clamped to the slice).
    ///
    /// # Safety
    /// No two live references may overlap; the slice must outlive them.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn range(&self, a: usize, b: usize) -> &mut [T] {
        let (a, b) = (a.min(self.len), b.min(self.len));
        std::slice::from_raw_parts_mut(self.ptr.add(a), b.saturating_sub(a))
    }

    /// Item i.
    ///
    /// # Safety
    /// No other live reference to item i; i < len; the slice must outlive the reference.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn get(&self, i: usize) -> &mut T {
        debug_assert!(i < self.len);
        &mut *self.ptr.add(i)
    }

    /// Raw pointer to the first item.
    pub fn as_ptr(&self) -> *mut T {
        self.ptr
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every item is computed once and comes back in index order;
    /// sizes from 1 (no worker) to more participants than items.
    #[test]
    fn map_covers_every_item_once_in_order() {
        for size in [1, 2, 3, 5] {
            let team = Team::new(size);
            for n in [0, 1, 7, 100] {
                for _ in 0..50 {
                    let out = team.map(n, |i| i * i);
                    assert_eq!(out.len(), n);
                    for (i, v) in out.iter().enumerate() {
                        assert_eq!(*v, i * i);
                    }
                }
            }
        }
    }

    /// A participant that stalls (here: sleeps on its first item) delays the section by that
    /// item only: the caller takes the rest of the stalled share.
    #[test]
    fn idle_participants_take_unclaimed_items_of_a_stalled_share() {
        let team = Team::new(2);
        let caller = std::thread::current().id();
        let out = team.map(10, |i| {
            let me = std::thread::current().id();
            if me != caller && i >= 5 {
                std::thread::sleep(Duration::from_millis(50));
            }
            me == caller
        });
        assert!(out[..5].iter().all(|&c| c), "the caller runs its own share");
        let taken = out[5..].iter().filter(|&&c| c).count();
        assert!(
            taken >= 4,
            "the caller took {taken} of the 5 items of the stalled share"
        );
    }

    /// A map inside a job of the same team, and maps from two threads at once, run (serially
    /// where the team is busy) and give every item.
    #[test]
    fn nested_and_concurrent_calls_complete() {
        let team = Team::new(2);
        let out = team.map(4, |i| team.map(3, |j| 10 * i + j).iter().sum::<usize>());
        assert_eq!(out, vec![3, 33, 63, 93]);
        std::thread::scope(|s| {
            let a = s.spawn(|| (0..200).map(|_| team.map(50, |i| i).len()).sum::<usize>());
            let b = s.spawn(|| (0..200).map(|_| team.map(50, |i| i).len()).sum::<usize>());
            assert_eq!(a.join().unwrap() + b.join().unwrap(), 2 * 200 * 50);
        });
    }

    /// A panic on a worker reaches the caller, and the team still works afterwards.
    #[test]
    fn worker_panic_is_raised_in_the_caller() {
        let team = Team::new(2);
        let r = catch_unwind(AssertUnwindSafe(|| {
            team.run(&|t| {
                if t == 1 {
                    panic!("worker fails");
                }
            })
        }));
        assert!(r.is_err());
        assert_eq!(team.map(4, |i| i + 1), vec![1, 2, 3, 4]);
    }

    /// Workers park after [`SPIN`] and wake for the next job.
    #[test]
    fn parked_workers_wake_up() {
        let team = Team::new(3);
        assert_eq!(team.map(3, |i| i), vec![0, 1, 2]);
        std::thread::sleep(SPIN * 3);
        assert_eq!(team.map(6, |i| 2 * i), vec![0, 2, 4, 6, 8, 10]);
    }
}
