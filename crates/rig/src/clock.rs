//! Waiting for a deadline with low jitter: sleep, then spin.
//!
//! `std::thread::sleep` on Linux wakes up late by the timer slack (50 µs by default) plus the
//! scheduler's latency; a pure spin burns a core. The hybrid sleeps until `margin` before the
//! deadline and spins (with [`std::hint::spin_loop`]) for the rest, so the wake-up error is
//! that of reading the clock as long as the sleep overshoots by less than `margin`.

use std::time::{Duration, Instant};

/// Waits until `deadline`: sleeps until `margin` before it, then spins. Returns at once if the
/// deadline has passed.
pub fn sleep_until(deadline: Instant, margin: Duration) {
    let now = Instant::now();
    if deadline <= now {
        return;
    }
    let left = deadline - now;
    if left > margin {
        std::thread::sleep(left - margin);
    }
    while Instant::now() < deadline {
        std::hint::spin_loop();
    }
}

/// Asks the scheduler to run the calling thread under `SCHED_FIFO` at `priority` (1–99) and
/// locks the process's memory (`mlockall(MCL_CURRENT | MCL_FUTURE)`), as real-time rig loops
/// do on Linux: a ready real-time thread preempts every ordinary one, so the wake-up no
/// longer waits for other processes' time slices. Needs `CAP_SYS_NICE` (root, or an
/// `rtprio` limit); the kernel's real-time throttling (by default 95 % of each second) keeps
/// a runaway loop from locking the machine.
///
/// # Errors
/// A message with the OS error if the policy cannot be set (the caller runs on without it),
/// or on systems other than Linux.
pub fn try_realtime(priority: i32) -> Result<(), String> {
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param {
            sched_priority: priority.clamp(1, 99),
        };
        // SAFETY: plain system calls on the calling thread / process with a valid pointer to
        // a stack value that outlives the call.
        let rc = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
        if rc != 0 {
            return Err(format!(
                "SCHED_FIFO priority {priority}: {}",
                std::io::Error::last_os_error()
            ));
        }
        // Page faults in the loop would cost milliseconds; failure to lock is not fatal.
        // SAFETY: as above, no pointers.
        let _ = unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) };
        Ok(())
    }
    #[cfg(not(target_os = "linux"))]
    {
        Err(format!(
            "real-time priority {priority}: only supported on Linux"
        ))
    }
}

/// Percentiles of a sample (nearest-rank on the sorted values; empty input gives zeros).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Largest value.
    pub max: f64,
    /// Number of values.
    pub n: usize,
}

impl Percentiles {
    /// Nearest-rank percentiles (the value of rank `⌈p·n⌉`) of `values` (sorted in place).
    pub fn of(values: &mut [f64]) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        values.sort_by(|a, b| a.total_cmp(b));
        let n = values.len();
        let rank = |p: f64| values[((p * n as f64).ceil() as usize).clamp(1, n) - 1];
        Self {
            p50: rank(0.5),
            p99: rank(0.99),
            max: values[n - 1],
            n,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentiles_of_1_to_100() {
        // Nearest rank of 1..=100: p50 is the 50th value, p99 the 99th.
        let mut v: Vec<f64> = (1..=100).rev().map(f64::from).collect();
        let p = Percentiles::of(&mut v);
        assert_eq!((p.p50, p.p99, p.max, p.n), (50.0, 99.0, 100.0, 100));
        assert_eq!(Percentiles::of(&mut []), Percentiles::default());
    }

    #[test]
    fn sleep_until_never_returns_early() {
        let d = Instant::now() + Duration::from_millis(3);
        sleep_until(d, Duration::from_micros(200));
        assert!(Instant::now() >= d);
    }
}
