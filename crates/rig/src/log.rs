//! Lossless CSV logging off the control thread.
//!
//! The control loop hands its rows to an unbounded channel (never blocks, never drops); a
//! logger thread writes each as one CSV row and flushes the file whenever the channel is
//! empty, so what the loop produced reaches the operating system within about one period even
//! if the process is then killed. [`Logger::finish`] drains the channel, flushes and reports
//! the row count; the runtime calls it on every stop path.
//!
//! One row per sensor frame the loop received (oldest first; a period that found several
//! frames logs each, a period that found none logs nothing), plus a final stop row after any
//! stop but completion. Columns (a header line first; numbers in Rust's shortest round-trip
//! form, so nothing is lost) — cart:
//! `k, t, t_nominal, t_wall, seq, z, theta, phi, dz, dtheta, v, v_sent, u_ctrl, status`; arm:
//! `k, t, t_nominal, t_wall, seq, theta1, theta2, phi1, phi2, dtheta1, dtheta2, v, v_sent, u_ctrl, status`.
//! `t` is the time the measurement belongs to: the rig's own stamp of the frame (the
//! microcontroller's clock, or the emulator's plant clock) from the run's first frame, so late
//! wake-ups of the PC loop do not distort it and a rig sampling at a fixed rate gives uniform
//! `t` as `pendulab identify` expects. `k` is the loop period that received the frame,
//! `t_nominal = k·ts` its deadline and `t_wall` its measured wake-up (both from the loop's
//! start): `t_wall − t_nominal` is the wake-up lateness. `theta`/`theta2` are upright-zero
//! (pendulab's convention) and `phi`/`phi2 = θ − π` are measured from the hanging rest (the
//! convention of `data/rig/`), `phi1 = θ₁`. Angles are logged **raw**, as the encoders count
//! them (multi-turn: a pendulum raised the other way round reads `2π` more, and an encoder
//! that slips a turn shows it), although the controller saw the pendulum angle wrapped about
//! its equilibrium (`RunConfig::pendulum_centre`). `v` is the voltage the rig had applied
//! when it took the sample (the command the frame echoes, after the loop's clamp; 0 before
//! the first command and for frames echoing the connect phase's disabled commands, i.e.
//! before the rig is enabled), `v_sent` the voltage the loop sent in period `k` and `u_ctrl` the controller's
//! output before the clamp; these two and the velocity estimates `dz, dtheta` are the loop's
//! values of period `k`, computed from the period's newest frame (rows of older frames read
//! in the same period repeat them); `status` is the rig's status bits. Every field is finite.
//! The stop row repeats the last measurement with `v = v_sent = u_ctrl = 0` and
//! `t` one loop period after the last frame's. So `pendulab identify cart-ls --data log.csv`
//! (columns `t, z, v`) and `pend-ls` (`t, z, phi`) read a cart log as it is.

use crate::RigError;
use crate::emulator::PlantKind;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

/// One row of the log: a sensor frame and what the loop did with it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Period index of the loop that received the frame.
    pub k: u64,
    /// The rig's time stamp of the measurement, from the run's first frame \[s\].
    pub t: f64,
    /// Deadline of period `k`, `k·ts` \[s\].
    pub t_nominal: f64,
    /// Measured wake-up of period `k` since the loop started \[s\].
    pub t_wall: f64,
    /// Sequence number of the sensor frame used (0: none yet).
    pub seq: u32,
    /// Positions `[z or θ₁, θ or θ₂]` (upright-zero angles).
    pub q: [f64; 2],
    /// Velocity estimates.
    pub dq: [f64; 2],
    /// Voltage the rig had applied when it took the sample \[V\].
    pub v: f64,
    /// Voltage the loop sent in period `k` \[V\].
    pub v_sent: f64,
    /// Controller output before the clamp \[V\].
    pub u_ctrl: f64,
    /// Rig status bits of the sensor frame used.
    pub status: u16,
}

/// The header line of a log of `plant`.
pub fn header(plant: PlantKind) -> &'static str {
    match plant {
        PlantKind::Cart => "k,t,t_nominal,t_wall,seq,z,theta,phi,dz,dtheta,v,v_sent,u_ctrl,status",
        PlantKind::Arm => {
            "k,t,t_nominal,t_wall,seq,theta1,theta2,phi1,phi2,dtheta1,dtheta2,v,v_sent,u_ctrl,status"
        }
    }
}

fn write_row(w: &mut impl Write, plant: PlantKind, s: &Sample) -> std::io::Result<()> {
    write!(
        w,
        "{},{},{},{},{},{},{},",
        s.k, s.t, s.t_nominal, s.t_wall, s.seq, s.q[0], s.q[1]
    )?;
    if plant == PlantKind::Arm {
        write!(w, "{},", s.q[0])?;
    }
    writeln!(
        w,
        "{},{},{},{},{},{},{}",
        s.q[1] - std::f64::consts::PI,
        s.dq[0],
        s.dq[1],
        s.v,
        s.v_sent,
        s.u_ctrl,
        s.status
    )
}

/// A CSV log being written by its own thread.
pub struct Logger {
    tx: Option<Sender<Sample>>,
    thread: Option<JoinHandle<Result<u64, std::io::Error>>>,
    path: PathBuf,
}

impl Logger {
    /// Creates (truncates) `path`, writes the header and starts the writer thread.
    ///
    /// # Errors
    /// [`RigError::Io`] naming the file.
    pub fn create(path: &Path, plant: PlantKind) -> Result<Self, RigError> {
        let file = File::create(path)
            .map_err(|e| RigError::io(format!("creating the log {}", path.display()), e))?;
        let mut w = BufWriter::with_capacity(1 << 16, file);
        writeln!(w, "{}", header(plant))
            .and_then(|_| w.flush())
            .map_err(|e| RigError::io(format!("writing the log {}", path.display()), e))?;
        let (tx, rx) = channel::<Sample>();
        let thread = std::thread::Builder::new()
            .name("rig-logger".into())
            .spawn(move || writer(w, plant, rx))
            .map_err(|e| RigError::io("starting the logger thread", e))?;
        Ok(Self {
            tx: Some(tx),
            thread: Some(thread),
            path: path.to_path_buf(),
        })
    }

    /// Queues one sample (never blocks). Returns `false` if the writer thread has stopped (on
    /// an I/O error, reported by [`Logger::finish`]).
    #[inline]
    pub fn log(&self, s: Sample) -> bool {
        self.tx.as_ref().is_some_and(|tx| tx.send(s).is_ok())
    }

    /// Drains the queue, flushes the file and returns the number of rows written.
    ///
    /// # Errors
    /// [`RigError::Io`] naming the file if any write failed.
    pub fn finish(mut self) -> Result<u64, RigError> {
        self.finish_inner()
    }

    fn finish_inner(&mut self) -> Result<u64, RigError> {
        self.tx = None;
        match self.thread.take() {
            Some(t) => match t.join() {
                Ok(Ok(n)) => Ok(n),
                Ok(Err(e)) => Err(RigError::io(
                    format!("writing the log {}", self.path.display()),
                    e,
                )),
                Err(_) => Err(RigError::ThreadPanicked("logger")),
            },
            None => Ok(0),
        }
    }
}

impl Drop for Logger {
    fn drop(&mut self) {
        let _ = self.finish_inner();
    }
}

fn writer(
    mut w: BufWriter<File>,
    plant: PlantKind,
    rx: Receiver<Sample>,
) -> Result<u64, std::io::Error> {
    let mut n = 0u64;
    // Block for the next sample, write everything queued, flush when the queue is empty.
    while let Ok(s) = rx.recv() {
        write_row(&mut w, plant, &s)?;
        n += 1;
        while let Ok(s) = rx.try_recv() {
            write_row(&mut w, plant, &s)?;
            n += 1;
        }
        w.flush()?;
    }
    w.flush()?;
    w.get_ref().sync_data()?;
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_exactly() {
        let dir = std::env::temp_dir().join(format!("pendulab-rig-log-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("log.csv");
        let log = Logger::create(&path, PlantKind::Cart).unwrap();
        let s = Sample {
            k: 7,
            t: 0.007,
            t_nominal: 0.006,
            t_wall: 0.0070001,
            seq: 9,
            q: [0.1 + 0.2, -1.0 / 3.0],
            dq: [1e-300, -0.0],
            v: 4.99984741210937,
            v_sent: -0.5,
            u_ctrl: 12.5,
            status: 5,
        };
        for k in 0..1000 {
            assert!(log.log(Sample { k, ..s }));
        }
        assert_eq!(log.finish().unwrap(), 1000);
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), header(PlantKind::Cart));
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), 1000);
        let f: Vec<f64> = rows[3].split(',').map(|x| x.parse().unwrap()).collect();
        // Shortest round-trip formatting gives back the identical f64 values.
        assert_eq!(f[0], 3.0);
        assert_eq!(f[1], 0.007);
        assert_eq!(f[2], 0.006);
        assert_eq!(f[5], 0.1 + 0.2);
        assert_eq!(f[6], -1.0 / 3.0);
        assert_eq!(f[7], -1.0 / 3.0 - std::f64::consts::PI);
        assert_eq!(f[8], 1e-300);
        assert_eq!(f[10], 4.99984741210937);
        assert_eq!(f[11], -0.5);
        std::fs::remove_dir_all(&dir).ok();
    }
}
