//! Waiting for a deadline with low jitter: sleep, then spin.
//!
//! `std::thread::sleep` on Linux wakes up late by the timer slack (50 µs by default) plus the
//! scheduler's latency; a pure spin burns a core. The hybrid sleeps until `margin` before the
//! deadline and spins (with [`std::hint::spin_loop`]) for the rest, so the wake-up error is
//! that of reading the clock as long as the sleep overshoots by less than `margin`.

use std::time::{Duration, Instant};

/// Why the scheduler refused [`try_realtime`] or [`pin_to_cpu`] (the loop then runs on
/// without it and says so). The OS error, where there is one, is the
/// [`std::error::Error::source`].
#[derive(Debug, thiserror::Error)]
pub enum SchedError {
    /// `sched_setscheduler(SCHED_FIFO)` refused (usually: no `CAP_SYS_NICE` or `rtprio`
    /// limit).
    #[error("SCHED_FIFO priority {priority}")]
    Realtime {
        /// The priority asked for (1–99).
        priority: i32,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// `sched_setaffinity` refused the CPU.
    #[error("CPU {cpu}")]
    Pin {
        /// The CPU asked for.
        cpu: usize,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The CPU's number is beyond the affinity mask.
    #[error("CPU {cpu}: beyond the affinity mask of {max} CPUs")]
    CpuOutOfRange {
        /// The CPU asked for.
        cpu: usize,
        /// The mask's size.
        max: usize,
    },
    /// Not available on this operating system (Linux only).
    #[error("{0}: only supported on Linux")]
    Unsupported(
        /// What was asked for.
        &'static str,
    ),
}

impl SchedError {
    /// The message with the OS error, on one line (`"SCHED_FIFO priority 80: Operation not
    /// permitted (os error 1)"`), for the run's `scheduling` line.
    pub fn describe(&self) -> String {
        match std::error::Error::source(self) {
            Some(s) => format!("{self}: {s}"),
            None => self.to_string(),
        }
    }
}

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
/// [`SchedError::Realtime`] with the OS error if the policy cannot be set (the caller runs on
/// without it); [`SchedError::Unsupported`] on systems other than Linux.
pub fn try_realtime(priority: i32) -> Result<(), SchedError> {
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param {
            sched_priority: priority.clamp(1, 99),
        };
        // SAFETY: plain system calls on the calling thread / process with a valid pointer to
        // a stack value that outlives the call.
        let rc = unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) };
        if rc != 0 {
            return Err(SchedError::Realtime {
                priority,
                source: std::io::Error::last_os_error(),
            });
        }
        // Page faults in the loop would cost milliseconds; failure to lock is not fatal.
        // SAFETY: as above, no pointers.
        let _ = unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) };
        Ok(())
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = priority;
        Err(SchedError::Unsupported("real-time priority"))
    }
}

/// Pins the calling thread to CPU `cpu` (`sched_setaffinity`), as real-time rig PCs do with a
/// core kept free of other work (`isolcpus=` on the kernel command line): the loop then never
/// migrates and never shares its core's caches with a build.
///
/// # Errors
/// [`SchedError::CpuOutOfRange`] for a CPU beyond the affinity mask, [`SchedError::Pin`] with
/// the OS error if the mask is refused (e.g. no such CPU), [`SchedError::Unsupported`] off
/// Linux.
pub fn pin_to_cpu(cpu: usize) -> Result<(), SchedError> {
    #[cfg(target_os = "linux")]
    {
        if cpu >= libc::CPU_SETSIZE as usize {
            return Err(SchedError::CpuOutOfRange {
                cpu,
                max: libc::CPU_SETSIZE as usize,
            });
        }
        // SAFETY: cpu_set_t is plain data; CPU_ZERO/CPU_SET write within it (index checked
        // above); sched_setaffinity reads `size_of` bytes from a valid pointer.
        let rc = unsafe {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            libc::CPU_ZERO(&mut set);
            libc::CPU_SET(cpu, &mut set);
            libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set)
        };
        if rc != 0 {
            return Err(SchedError::Pin {
                cpu,
                source: std::io::Error::last_os_error(),
            });
        }
        Ok(())
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = cpu;
        Err(SchedError::Unsupported("pinning to a CPU"))
    }
}

/// CPU time consumed by the calling thread (`CLOCK_THREAD_CPUTIME_ID`): user and system
/// time, not the time it waited for a CPU. Wall time minus this over an interval in which the
/// thread never blocks is the time it was kept off the CPU (by other threads, the kernel or,
/// on a virtual machine, the hypervisor). `None` off Unix or if the clock is unavailable.
pub fn thread_cpu_time() -> Option<Duration> {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: a valid pointer to a stack value that outlives the call.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        (rc == 0).then(|| Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32))
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// CPU time the hypervisor gave to others while this machine's virtual CPUs were ready to run
/// ("steal", the eighth number of the `cpu` line of Linux's `/proc/stat`), summed over all
/// CPUs, in seconds since boot. The difference of two readings tells whether a stall of the
/// loop coincided with the host taking the CPU away, which no priority inside the guest can
/// prevent.
///
/// `None` off Linux, without `/proc`, or if the line cannot be parsed.
pub fn host_steal_seconds() -> Option<f64> {
    #[cfg(target_os = "linux")]
    {
        let text = std::fs::read_to_string("/proc/stat").ok()?;
        parse_steal(&text).map(|ticks| {
            // SAFETY: sysconf has no pointer arguments.
            let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
            ticks as f64 / if hz > 0 { hz as f64 } else { 100.0 }
        })
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

/// The steal field (clock ticks) of the aggregate `cpu` line of a `/proc/stat` text.
fn parse_steal(stat: &str) -> Option<u64> {
    let line = stat.lines().find(|l| l.starts_with("cpu "))?;
    // cpu user nice system idle iowait irq softirq steal ...
    line.split_whitespace().nth(8)?.parse().ok()
}

/// Percentiles of a sample (nearest-rank), its mean and its extremes; empty input gives zeros.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Largest value.
    pub max: f64,
    /// Arithmetic mean.
    pub mean: f64,
    /// Number of values.
    pub n: usize,
}

impl Percentiles {
    /// Exact nearest-rank percentiles (the value of rank `⌈p·n⌉`) of `values` (sorted in
    /// place), the exact mean and maximum.
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
            mean: values.iter().sum::<f64>() / n as f64,
            n,
        }
    }
}

/// Fixed-memory statistics of a stream of non-negative durations \[s\]: a log-scale
/// histogram for percentiles plus the exact count, sum (mean) and maximum.
///
/// Bin `i ≥ 1` holds the values in `[LO·(1+R)^(i−1), LO·(1+R)^i)` with `LO` = [`Self::LO`]
/// (1 ns) and `R` = [`Self::R`] (1 %); bin 0 holds everything below `LO` (and negative or
/// NaN input, counted as 0), the last bin everything from `HI` = [`Self::HI`] (1000 s) on.
/// A percentile is reported as the upper edge of the bin holding the nearest-rank value,
/// capped at the exact maximum, so for a true percentile `q` the estimate `q̂` satisfies
/// `q ≤ q̂ ≤ max(q·(1+R), LO)` (for `q < HI`): a resolution of 1 % or 1 ns, whichever is
/// larger. Memory is `(ln(HI/LO)/ln(1+R) + 2)` counters (≈ 2 780 × 8 bytes), however long
/// the run — what an endless run (`--duration 0`) needs. The scheme is that of
/// HDR-histogram-style log-bucketed latency recorders (G. Tene, *HdrHistogram*), reduced to
/// a single geometric bucket ladder.
#[derive(Debug, Clone)]
pub struct Histogram {
    bins: Vec<u64>,
    n: u64,
    sum: f64,
    max: f64,
    ln_step: f64,
}

impl Default for Histogram {
    fn default() -> Self {
        Self::new()
    }
}

impl Histogram {
    /// Lower edge of the ladder \[s\].
    pub const LO: f64 = 1e-9;
    /// Upper edge of the ladder \[s\].
    pub const HI: f64 = 1e3;
    /// Relative width of a bin.
    pub const R: f64 = 0.01;

    /// An empty histogram (allocates its fixed bins once).
    pub fn new() -> Self {
        let ln_step = Self::R.ln_1p();
        let n_bins = ((Self::HI / Self::LO).ln() / ln_step).ceil() as usize + 2;
        Self {
            bins: vec![0; n_bins],
            n: 0,
            sum: 0.0,
            max: 0.0,
            ln_step,
        }
    }

    /// Number of bins (fixed at construction).
    pub fn bin_count(&self) -> usize {
        self.bins.len()
    }

    /// Upper edge of bin `i` (`LO·(1+R)^i`).
    fn upper(&self, i: usize) -> f64 {
        Self::LO * (i as f64 * self.ln_step).exp()
    }

    /// Records one value (negative or NaN values are recorded as 0).
    #[inline]
    pub fn record(&mut self, v: f64) {
        let v = if v > 0.0 { v } else { 0.0 };
        let last = self.bins.len() - 1;
        let i = if v < Self::LO {
            0
        } else {
            // Bin from the logarithm, then corrected against the same edges `upper` reports,
            // so rounding in ln/exp can never put a value outside its reported bin.
            let mut i = (((v / Self::LO).ln() / self.ln_step).floor() as usize + 1).min(last);
            while i > 1 && v < self.upper(i - 1) {
                i -= 1;
            }
            while i < last && v >= self.upper(i) {
                i += 1;
            }
            i
        };
        self.bins[i] += 1;
        self.n += 1;
        self.sum += v;
        if v > self.max {
            self.max = v;
        }
    }

    /// Nearest-rank percentile `p ∈ (0, 1]` to the stated resolution (0 if empty).
    pub fn percentile(&self, p: f64) -> f64 {
        if self.n == 0 {
            return 0.0;
        }
        let rank = ((p * self.n as f64).ceil() as u64).clamp(1, self.n);
        let mut seen = 0u64;
        for (i, &c) in self.bins.iter().enumerate() {
            seen += c;
            if seen >= rank {
                return self.upper(i).min(self.max);
            }
        }
        self.max
    }

    /// p50, p99 (to the resolution), exact maximum, mean and count.
    pub fn summary(&self) -> Percentiles {
        if self.n == 0 {
            return Percentiles::default();
        }
        Percentiles {
            p50: self.percentile(0.5),
            p99: self.percentile(0.99),
            max: self.max,
            mean: self.sum / self.n as f64,
            n: self.n as usize,
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
        // Mean of 1..=100 is 101/2.
        assert_eq!(p.mean, 50.5);
        assert_eq!(Percentiles::of(&mut []), Percentiles::default());
    }

    #[test]
    fn pinning_to_a_cpu_that_does_not_exist_is_an_error() {
        assert!(pin_to_cpu(usize::MAX).is_err());
        #[cfg(target_os = "linux")]
        {
            // CPU 0 always exists; pin a scratch thread (not the test harness's) to it.
            std::thread::spawn(|| {
                pin_to_cpu(0).unwrap();
                // SAFETY: no arguments.
                assert_eq!(unsafe { libc::sched_getcpu() }, 0);
            })
            .join()
            .unwrap();
        }
    }

    #[test]
    fn thread_cpu_time_counts_work_not_sleep() {
        let Some(c0) = thread_cpu_time() else {
            return; // no per-thread CPU clock on this OS
        };
        std::thread::sleep(Duration::from_millis(30));
        let c1 = thread_cpu_time().unwrap();
        // Sleeping costs microseconds of CPU, not 30 ms (bound: 10 ms, generous for a
        // loaded machine's wake-up path).
        assert!(c1 - c0 < Duration::from_millis(10), "{:?}", c1 - c0);
        let t = Instant::now();
        let mut x = 0u64;
        while t.elapsed() < Duration::from_millis(30) {
            x = std::hint::black_box(x.wrapping_add(1));
        }
        let c2 = thread_cpu_time().unwrap();
        // 30 ms of spinning is at most 30 ms of CPU (plus the clock's granularity).
        assert!(c2 - c1 <= Duration::from_millis(31), "{:?}", c2 - c1);
        assert!(c2 > c1);
    }

    #[test]
    fn steal_is_the_eighth_number_of_the_cpu_line() {
        let stat = "cpu  1522121 0 118638 217946 2932 0 1388 6586 0 0\ncpu0 1 2 3 4 5 6 7 8 9 10\n";
        assert_eq!(parse_steal(stat), Some(6586));
        assert_eq!(parse_steal("cpu0 1 2 3 4 5 6 7 8\n"), None);
        assert_eq!(parse_steal("cpu  1 2 3\n"), None);
        assert_eq!(parse_steal("cpu  1 2 3 4 5 6 7 x\n"), None);
    }

    #[test]
    fn sleep_until_never_returns_early() {
        let d = Instant::now() + Duration::from_millis(3);
        sleep_until(d, Duration::from_micros(200));
        assert!(Instant::now() >= d);
    }

    /// A deterministic sample spanning 1 ns … 0.1 s log-uniformly, plus exact zeros and a
    /// cluster of equal values (SplitMix64 for the draws).
    fn sample() -> Vec<f64> {
        let mut z = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut x = z;
            x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((x ^ (x >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut v: Vec<f64> = (0..200_000).map(|_| 1e-9 * 1e8f64.powf(next())).collect();
        v.extend(std::iter::repeat_n(0.0, 500));
        v.extend(std::iter::repeat_n(1e-3, 3000));
        v
    }

    #[test]
    fn histogram_percentiles_agree_with_exact_ones_to_the_stated_resolution() {
        let values = sample();
        let mut h = Histogram::new();
        let bins = h.bin_count();
        for &x in &values {
            h.record(x);
        }
        // Fixed memory: recording never adds bins.
        assert_eq!(h.bin_count(), bins);
        assert!(bins < 3000, "{bins}");
        let mut sorted = values.clone();
        let exact = Percentiles::of(&mut sorted);
        let s = h.summary();
        // Exact count and maximum; the mean is the same sum in another order, equal to
        // rounding (200 000 terms: relative 1e-12 is far above the f64 summation error).
        assert_eq!(s.n, values.len());
        assert_eq!(s.max, exact.max);
        assert!(
            (s.mean - exact.mean).abs() <= 1e-12 * exact.mean,
            "{s:?} {exact:?}"
        );
        // Every percentile: the exact nearest-rank value q of the sorted sample against the
        // estimate q̂ with the documented bound q ≤ q̂ ≤ max(q·(1 + R), LO) (a tiny slack of
        // 1e-12 relative for exp/ln rounding of the bin edges).
        for p in [0.001, 0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999, 1.0] {
            let n = sorted.len();
            let q = sorted[((p * n as f64).ceil() as usize).clamp(1, n) - 1];
            let qh = h.percentile(p);
            let hi = (q * (1.0 + Histogram::R)).max(Histogram::LO) * (1.0 + 1e-12);
            assert!(q <= qh && qh <= hi, "p = {p}: exact {q}, histogram {qh}");
        }
        assert_eq!(s.p50, h.percentile(0.5));
        assert_eq!(s.p99, h.percentile(0.99));
        // The 1-to-100 µs sample: nearest rank p50 = 50 µs, p99 = 99 µs within 1 %.
        let mut h = Histogram::new();
        for i in (1..=100).rev() {
            h.record(f64::from(i) * 1e-6);
        }
        let s = h.summary();
        let us = |i: i32| f64::from(i) * 1e-6;
        assert!(s.p50 >= us(50) && s.p50 <= us(50) * 1.01, "{s:?}");
        assert!(s.p99 >= us(99) && s.p99 <= us(99) * 1.01, "{s:?}");
        assert_eq!(s.max, us(100));
        assert_eq!(Histogram::new().summary(), Percentiles::default());
    }
}
