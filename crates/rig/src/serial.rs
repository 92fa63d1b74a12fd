//! The protocol over a serial port (feature `serial`, off by default).
//!
//! A serial line carries the same frames back to back; [`SerialLink`] writes command frames
//! and decodes sensor frames out of the byte stream (the runtime uses it when
//! `RunConfig::serial` is set) with
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
    /// [`crate::ConfigError::SerialPort`] naming the port if it cannot be opened.
    pub fn open(path: &str, baud: u32) -> Result<Self, RigError> {
        let port = serialport::new(path, baud)
            .timeout(Duration::from_millis(1))
            .open()
            .map_err(|source| crate::ConfigError::SerialPort {
                path: path.to_string(),
                source,
            })?;
        Ok(Self {
            port,
            decoder: StreamDecoder::new(),
            buf: [0; 256],
        })
    }

    /// Writes one encoded frame.
    ///
    /// # Errors
    /// The port's I/O error.
    pub fn write_frame(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.port.write_all(bytes)
    }

    /// Writes one command frame.
    ///
    /// # Errors
    /// [`RigError::Io`].
    pub fn send(&mut self, frame: &CommandFrame) -> Result<(), RigError> {
        self.write_frame(&frame.encode())
            .map_err(|e| RigError::io("writing to the serial port", e))
    }

    /// Reads what has arrived (waiting at most the 1 ms timeout) into the decoder.
    ///
    /// # Errors
    /// The port's I/O error (a timeout is not one).
    pub fn poll(&mut self) -> std::io::Result<()> {
        let available = self.port.bytes_to_read().map_err(std::io::Error::other)?;
        if available == 0 {
            return Ok(());
        }
        match self.port.read(&mut self.buf) {
            Ok(n) => self.decoder.push(&self.buf[..n]),
            Err(e) if e.kind() == ErrorKind::TimedOut => {}
            Err(e) => return Err(e),
        }
        Ok(())
    }

    /// The next complete, checksummed sensor frame in the stream, if any (sequence and
    /// session checks are the caller's).
    pub fn next_frame(&mut self) -> Option<SensorFrame> {
        self.decoder
            .next_frame(SENSOR_LEN, KIND_SENSOR)
            .and_then(|f| SensorFrame::decode(&f).ok())
    }

    /// Bytes skipped while resynchronising.
    pub fn skipped(&self) -> u64 {
        self.decoder.skipped
    }
}
