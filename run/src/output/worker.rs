//! The writer thread of an output: a named thread at a lower priority than the solver
//! ([`lower_thread_priority`]) that consumes messages from a bounded channel. A full channel
//! makes the solver wait (back-pressure: nothing is dropped); a thread that ended (an error,
//! a panic) is joined at the next send and its error returned. The worker also keeps the time
//! the caller (the solver thread) spent on the output, for the run summary.

use super::lower_thread_priority;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// A writer thread fed messages `M`, ending with `Result<R, E>`.
pub struct Worker<M, R, E> {
    tx: Option<SyncSender<M>>,
    thread: Option<JoinHandle<Result<R, E>>>,
    /// Builds the error for what the thread itself did not say ("stopped early", "panicked").
    thread_error: fn(&str) -> E,
    /// Caller time spent on this output: sends, waits on a full channel, the final wait, and
    /// what [`Worker::charge`] adds.
    caller_time: Duration,
}

impl<M: Send + 'static, R: Send + 'static, E: Send + 'static> Worker<M, R, E> {
    /// Starts thread `name` running `body` over a channel of `queue` messages.
    /// `thread_error` words the errors of the thread's life.
    pub fn spawn(
        name: &str,
        queue: usize,
        thread_error: fn(&str) -> E,
        body: impl FnOnce(Receiver<M>) -> Result<R, E> + Send + 'static,
    ) -> Result<Self, E> {
        let started = Instant::now();
        let (tx, rx) = sync_channel::<M>(queue);
        let thread = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                // The outputs must not slow the solve: this thread, and the threads it starts
                // (they inherit it), yield the CPU to the solver.
                lower_thread_priority();
                body(rx)
            })
            .map_err(|e| thread_error(&format!("cannot start: {e}")))?;
        Ok(Worker {
            tx: Some(tx),
            thread: Some(thread),
            thread_error,
            caller_time: started.elapsed(),
        })
    }

    /// Adds caller time spent on this output elsewhere (its set-up, the snapshots).
    pub fn charge(&mut self, time: Duration) {
        self.caller_time += time;
    }

    /// Sends one message, waiting while the channel is full; `extra` is caller time spent
    /// making it. When the thread has ended, its error (or "stopped early").
    pub fn send(&mut self, msg: M, extra: Duration) -> Result<(), E> {
        let started = Instant::now();
        let sent = self.tx.as_ref().map(|tx| tx.send(msg));
        self.caller_time += started.elapsed() + extra;
        match sent {
            Some(Ok(())) => Ok(()),
            _ => Err(self
                .join()
                .err()
                .unwrap_or_else(|| (self.thread_error)("stopped early"))),
        }
    }

    /// Sends a last message if any (a thread that has ended already does not get it; `extra`
    /// is caller time spent making it), closes the channel and waits for the thread's result.
    /// Returns it with the caller time spent on this output in all.
    pub fn finish(mut self, last: Option<M>, extra: Duration) -> Result<(R, Duration), E> {
        let started = Instant::now();
        if let (Some(tx), Some(msg)) = (&self.tx, last) {
            // A closed channel means the thread ended with an error, returned by join().
            let _ = tx.send(msg);
        }
        let end = self.join()?;
        Ok((end, self.caller_time + extra + started.elapsed()))
    }

    fn join(&mut self) -> Result<R, E> {
        self.tx = None;
        match self.thread.take() {
            Some(t) => t
                .join()
                .unwrap_or_else(|_| Err((self.thread_error)("panicked"))),
            None => Err((self.thread_error)("already ended")),
        }
    }
}
