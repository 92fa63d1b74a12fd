//! The wire: the transport (UDP or serial), the session number, sending command frames and
//! receiving the fresh sensor frames of this session.

use super::RunConfig;
use crate::RigError;
use crate::protocol::{CommandFrame, RejectCounts, SensorFrame, SeqVerdict, SequenceGate};
use std::io::ErrorKind;
use std::net::{SocketAddr, UdpSocket};

/// A session number for this run: non-zero, different between runs (clock and process id
/// mixed by SplitMix64's finaliser).
pub(super) fn new_session() -> u32 {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(0);
    let mut z = nanos ^ ((std::process::id() as u64) << 32);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    ((z as u32) | 1).max(1)
}

/// How frames travel: datagrams on UDP, or a byte stream on a serial port.
pub(super) enum Transport {
    Udp(UdpSocket),
    #[cfg(feature = "serial")]
    Serial(Box<crate::serial::SerialLink>),
}

/// Judges one decoded frame; returns it if it is fresh and of `session`.
fn judge(
    session: u32,
    gate: &mut SequenceGate,
    rejects: &mut RejectCounts,
    f: SensorFrame,
) -> Option<SensorFrame> {
    if f.session != session {
        // Frames before the rig adopted this session carry another number.
        rejects.foreign_session += 1;
        return None;
    }
    match gate.check(f.seq) {
        SeqVerdict::Fresh { .. } => Some(f),
        v => {
            rejects.count_verdict(v);
            None
        }
    }
}

pub(super) struct Link {
    pub(super) transport: Transport,
    pub(super) session: u32,
    pub(super) seq: u32,
    pub(super) gate: SequenceGate,
    pub(super) rejects: RejectCounts,
    pub(super) buf: [u8; 2048],
}

impl Link {
    pub(super) fn send(
        &mut self,
        volts: f64,
        fl: u16,
        sensor_seq: u32,
    ) -> Result<u32, std::io::Error> {
        self.seq = self.seq.wrapping_add(1);
        let frame = CommandFrame {
            session: self.session,
            seq: self.seq,
            microvolts: CommandFrame::microvolts_of(volts),
            flags: fl,
            sensor_seq,
        };
        let sent = match &mut self.transport {
            Transport::Udp(socket) => socket.send(&frame.encode()).map(|_| ()),
            #[cfg(feature = "serial")]
            Transport::Serial(port) => port.write_frame(&frame.encode()),
        };
        match sent {
            Ok(()) => Ok(self.seq),
            // Loopback reports a vanished peer on the next call; the watchdog handles it.
            Err(e)
                if matches!(
                    e.kind(),
                    ErrorKind::ConnectionRefused | ErrorKind::WouldBlock
                ) =>
            {
                Ok(self.seq)
            }
            Err(e) => Err(e),
        }
    }

    /// Appends every fresh frame waiting to `out`, oldest first (the last is the newest).
    pub(super) fn receive(&mut self, out: &mut Vec<SensorFrame>) -> Result<(), std::io::Error> {
        #[cfg(feature = "serial")]
        if let Transport::Serial(port) = &mut self.transport {
            port.poll()?;
            while let Some(f) = port.next_frame() {
                if let Some(f) = judge(self.session, &mut self.gate, &mut self.rejects, f) {
                    out.push(f);
                }
            }
            return Ok(());
        }
        loop {
            let got = match &self.transport {
                Transport::Udp(socket) => socket.recv(&mut self.buf),
                #[cfg(feature = "serial")]
                Transport::Serial(_) => return Ok(()),
            };
            match got {
                Ok(n) => {
                    let f = match SensorFrame::decode(&self.buf[..n]) {
                        Ok(f) => f,
                        Err(e) => {
                            self.rejects.count_error(e);
                            continue;
                        }
                    };
                    if let Some(f) = judge(self.session, &mut self.gate, &mut self.rejects, f) {
                        out.push(f);
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == ErrorKind::ConnectionRefused => return Ok(()),
                Err(e) => return Err(e),
            }
        }
    }
}

pub(super) fn open_transport(config: &RunConfig) -> Result<Transport, RigError> {
    #[cfg(feature = "serial")]
    if let Some((path, baud)) = &config.serial {
        return Ok(Transport::Serial(Box::new(
            crate::serial::SerialLink::open(path, *baud)?,
        )));
    }
    let bind: SocketAddr = if config.connect.is_ipv4() {
        SocketAddr::from(([0, 0, 0, 0], 0))
    } else {
        SocketAddr::from(([0u16; 8], 0))
    };
    let socket = UdpSocket::bind(bind).map_err(|e| RigError::io("binding a UDP socket", e))?;
    socket
        .connect(config.connect)
        .map_err(|e| RigError::io(format!("connecting to {}", config.connect), e))?;
    socket
        .set_nonblocking(true)
        .map_err(|e| RigError::io("setting the socket non-blocking", e))?;
    Ok(Transport::Udp(socket))
}
