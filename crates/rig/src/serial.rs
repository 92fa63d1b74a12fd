//! The protocol over a serial port (feature `serial`, off by default).
//!
//! A serial line carries the same frames back to back; [`SerialLink`] writes command frames
//! and decodes sensor frames out of the byte stream with
//! [`crate::protocol::StreamDecoder`] (resynchronising on the magic and checksum). Built on the
//! `serialport` crate without its default features, so no system library is needed.

use crate::RigError;
use crate::protocol::{CommandFrame, KIND_SENSOR, SENSOR_LEN, SensorFrame, StreamDecoder};
use std::io::{ErrorKind, Read, Write};
use std::time::Duration;

/// A rig on a serial port.
pub struct SerialLink {
    port: Box<dyn serialport::SerialPort>,
    decoder: StreamDecoder,
    buf: [u8; 256],
}

impl SerialLink {
    /// Opens `path` (e.g. `/dev/ttyACM0`) at `baud` with a 1 ms read timeout.
    ///
    /// # Errors
    /// [`RigError::Config`] naming the port if it cannot be opened.
    pub fn open(path: &str, baud: u32) -> Result<Self, RigError> {
        let port = serialport::new(path, baud)
            .timeout(Duration::from_millis(1))
            .open()
            .map_err(|e| RigError::Config(format!("serial port {path}: {e}")))?;
        Ok(Self {
            port,
            decoder: StreamDecoder::new(),
            buf: [0; 256],
        })
    }

    /// Writes one command frame.
    ///
    /// # Errors
    /// [`RigError::Io`].
    pub fn send(&mut self, frame: &CommandFrame) -> Result<(), RigError> {
        self.port
            .write_all(&frame.encode())
            .map_err(|e| RigError::io("writing to the serial port", e))
    }

    /// Reads what has arrived and returns the newest complete sensor frame, if any.
    ///
    /// # Errors
    /// [`RigError::Io`].
    pub fn receive(&mut self) -> Result<Option<SensorFrame>, RigError> {
        match self.port.read(&mut self.buf) {
            Ok(n) => self.decoder.push(&self.buf[..n]),
            Err(e) if e.kind() == ErrorKind::TimedOut => {}
            Err(e) => return Err(RigError::io("reading the serial port", e)),
        }
        let mut newest = None;
        while let Some(f) = self.decoder.next_frame(SENSOR_LEN, KIND_SENSOR) {
            newest = SensorFrame::decode(&f).ok();
        }
        Ok(newest)
    }

    /// Bytes skipped while resynchronising.
    pub fn skipped(&self) -> u64 {
        self.decoder.skipped
    }
}
