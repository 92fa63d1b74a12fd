//! What a run reports: why it stopped ([`StopReason`]), what the loop measured of itself
//! ([`LoopStats`]) and the whole [`RunReport`]; and how one period's timing is judged.

use crate::clock::Percentiles;
use crate::protocol::RejectCounts;
use std::fmt;
use std::time::Duration;

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The duration elapsed.
    Completed,
    /// The stop flag was raised (Ctrl-C, SIGTERM).
    Interrupted,
    /// No fresh sensor frame for the configured number of periods.
    Watchdog,
    /// The drive left its travel limit.
    TravelLimit,
    /// The pendulum left the balance window.
    AngleWindow,
    /// A measurement or command was not finite.
    NonFinite,
    /// The socket failed.
    Io,
}

impl StopReason {
    /// The process exit status `pendulab rig run` returns: 0 completed, 2 interrupted,
    /// 3 watchdog, 4 travel limit, 5 angle window, 6 non-finite value, 7 I/O.
    pub fn exit_code(self) -> u8 {
        match self {
            StopReason::Completed => 0,
            StopReason::Interrupted => 2,
            StopReason::Watchdog => 3,
            StopReason::TravelLimit => 4,
            StopReason::AngleWindow => 5,
            StopReason::NonFinite => 6,
            StopReason::Io => 7,
        }
    }

    /// A short name (`completed`, `interrupted`, `watchdog`, `travel-limit`,
    /// `angle-window`, `non-finite`, `io`).
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Completed => "completed",
            StopReason::Interrupted => "interrupted",
            StopReason::Watchdog => "watchdog",
            StopReason::TravelLimit => "travel-limit",
            StopReason::AngleWindow => "angle-window",
            StopReason::NonFinite => "non-finite",
            StopReason::Io => "io",
        }
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the loop measured of itself. Times in seconds; percentiles from fixed-memory
/// [`Histogram`]s (resolution 1 % or 1 ns), maxima and means exact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoopStats {
    /// `|period − ts|` of consecutive wake-ups.
    pub jitter: Percentiles,
    /// Wake-up lateness after the deadline.
    pub lateness: Percentiles,
    /// From wake-up to the command sent.
    pub compute: Percentiles,
    /// Command sent → the rig reports it applied (echoed sequence number).
    pub round_trip: Percentiles,
    /// Periods whose command was sent after the next deadline.
    pub deadline_misses: u64,
    /// Of [`Self::deadline_misses`], those the loop thread would have made had it kept its CPU:
    /// the time it spent off the CPU since the deadline — a late wake-up plus the wall time of
    /// the period's work minus the thread's CPU time for it ([`crate::clock::thread_cpu_time`])
    /// — exceeds the amount by which the command was late. The OS or, on a virtual machine, the
    /// hypervisor ran something else. The rest, `deadline_misses − descheduled_misses`, are
    /// overruns: the loop's own work did not fit in the period. Without a per-thread CPU clock
    /// only the late wake-up counts as time off the CPU.
    pub descheduled_misses: u64,
    /// Distinct stalls: runs of consecutive periods in which the thread was off the CPU for
    /// more than a whole period. A stall of `d` seconds costs about `d / ts` periods, which the
    /// loop then runs back to back.
    pub stalls: u64,
    /// The longest time off the CPU within one period (s), as defined for
    /// [`Self::descheduled_misses`].
    pub longest_off_cpu: f64,
    /// Periods run without a fresh sensor frame.
    pub stale_periods: u64,
    /// The longest time without a fresh sensor frame, in periods (skipped periods included).
    pub longest_stale_run: u64,
    /// Stale periods in which the last command computed from a fresh measurement was sent
    /// again ([`Safety::stale_hold_periods`]).
    pub held_commands: u64,
    /// Stale periods beyond the hold, in which 0 V was sent.
    pub zero_commands: u64,
    /// Periods skipped after a stall: deadlines already passed when the loop came back, not
    /// replayed back to back (the next period reads every frame that waited).
    pub skipped_periods: u64,
    /// Fresh sensor frames whose rig time stamp is earlier than the previous fresh frame's
    /// (the rig's clock went backwards: its log times are not monotonic). Warned about in
    /// the summary.
    pub rig_time_backwards: u64,
    /// Commands clamped by the voltage limit.
    pub clamped: u64,
    /// Sensor frames rejected, by reason.
    pub rejects: RejectCounts,
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunReport {
    /// Why it stopped.
    pub reason: StopReason,
    /// Human-readable detail (which limit, which value).
    pub detail: String,
    /// Periods of the schedule up to and including the stop's (skipped periods included).
    pub samples: u64,
    /// Rows the logger wrote (one per sensor frame received, plus the stop row).
    pub logged: Option<u64>,
    /// Loop statistics.
    pub stats: LoopStats,
    /// The last measurement `y`.
    pub last_y: [f64; 4],
    /// The scheduling the loop ran under (`"ordinary"`, `"SCHED_FIFO 80"`, or why not).
    pub scheduling: String,
    /// The loop period \[s\].
    pub ts: f64,
}

impl fmt::Display for RunReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let us = |p: &Percentiles| {
            format!(
                "p50 {:.1} µs, p99 {:.1} µs, max {:.1} µs, mean {:.1} µs",
                p.p50 * 1e6,
                p.p99 * 1e6,
                p.max * 1e6,
                p.mean * 1e6
            )
        };
        let s = &self.stats;
        writeln!(f, "stop: {} ({})", self.reason, self.detail)?;
        writeln!(f, "samples: {}", self.samples)?;
        writeln!(f, "scheduling: {}", self.scheduling)?;
        if let Some(n) = self.logged {
            writeln!(f, "logged: {n}")?;
        }
        writeln!(f, "period jitter: {}", us(&s.jitter))?;
        writeln!(f, "wake-up lateness: {}", us(&s.lateness))?;
        writeln!(f, "computation: {}", us(&s.compute))?;
        writeln!(f, "round trip: {}", us(&s.round_trip))?;
        writeln!(
            f,
            "deadline misses: {} ({} overruns, {} while descheduled; {} stalls longer than a period, longest {:.0} µs; {} periods skipped), stale periods: {}, clamped commands: {}",
            s.deadline_misses,
            s.deadline_misses - s.descheduled_misses,
            s.descheduled_misses,
            s.stalls,
            s.longest_off_cpu * 1e6,
            s.skipped_periods,
            s.stale_periods,
            s.clamped
        )?;
        writeln!(
            f,
            "stale data: {} periods, longest {} periods ({:.1} ms), held commands {}, 0 V commands {}",
            s.stale_periods,
            s.longest_stale_run,
            s.longest_stale_run as f64 * self.ts * 1e3,
            s.held_commands,
            s.zero_commands
        )?;
        write!(f, "rejected sensor frames: {}", s.rejects)?;
        if s.rig_time_backwards > 0 {
            write!(
                f,
                "\nwarning: the rig's time stamp went backwards {} times (log times are not monotonic)",
                s.rig_time_backwards
            )?;
        }
        Ok(())
    }
}

/// How one period went: whether its command missed the next deadline and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PeriodTiming {
    /// Time off the CPU since the deadline: the late wake-up plus the wall time of the work
    /// minus its CPU time.
    pub(super) off_cpu: Duration,
    /// The command was sent after the next deadline.
    pub(super) missed: bool,
    /// It missed, and by less than the time spent off the CPU.
    pub(super) descheduled: bool,
}

impl PeriodTiming {
    /// From the wake-up's lateness after the deadline, the wall time of the period's work
    /// (wake-up to command sent), the thread's CPU time for that work (if measured) and the
    /// period.
    pub(super) fn of(
        late: Duration,
        work: Duration,
        cpu_work: Option<Duration>,
        period: Duration,
    ) -> Self {
        let off_cpu = late + cpu_work.map_or(Duration::ZERO, |c| work.saturating_sub(c));
        let miss_by = (late + work).saturating_sub(period);
        let missed = miss_by > Duration::ZERO;
        Self {
            off_cpu,
            missed,
            descheduled: missed && off_cpu > miss_by,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::PeriodTiming;
    use std::time::Duration;

    fn us(v: u64) -> Duration {
        Duration::from_micros(v)
    }

    #[test]
    fn a_period_that_fits_is_no_miss() {
        let p = PeriodTiming::of(us(5), us(30), Some(us(30)), us(200));
        assert!(!p.missed && !p.descheduled);
        assert_eq!(p.off_cpu, us(5));
    }

    #[test]
    fn work_that_used_the_cpu_all_along_is_an_overrun() {
        // Woken on time, 250 µs of work on the CPU in a 200 µs period: the loop's own fault.
        let p = PeriodTiming::of(us(0), us(250), Some(us(250)), us(200));
        assert!(p.missed && !p.descheduled);
    }

    #[test]
    fn work_interrupted_by_a_stall_is_a_descheduled_miss() {
        // 30 µs of CPU spread over 3 ms of wall time: 2.97 ms off the CPU, missed by 2.8 ms.
        let p = PeriodTiming::of(us(0), us(3000), Some(us(30)), us(200));
        assert!(p.missed && p.descheduled);
        assert_eq!(p.off_cpu, us(2970));
    }

    #[test]
    fn a_late_wake_up_counts_as_time_off_the_cpu() {
        // Woken 1 ms late (with or without a CPU clock): missed by 0.83 ms < 1 ms off the CPU.
        for cpu in [Some(us(30)), None] {
            let p = PeriodTiming::of(us(1000), us(30), cpu, us(200));
            assert!(p.missed && p.descheduled, "{cpu:?}");
        }
    }

    #[test]
    fn a_short_stall_does_not_excuse_a_long_overrun() {
        // 50 µs off the CPU cannot explain missing by 300 µs.
        let p = PeriodTiming::of(us(50), us(450), Some(us(450)), us(200));
        assert!(p.missed && !p.descheduled);
    }
}
