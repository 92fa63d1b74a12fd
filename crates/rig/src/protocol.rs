//! The wire protocol between the controller runtime and a rig (real or emulated), version 1.
//!
//! Two fixed-size little-endian frames, each closed by a CRC-16/CCITT-FALSE checksum over
//! every byte before it (polynomial `0x1021`, initial value `0xFFFF`, no reflection, no final
//! XOR; the check value of the ASCII string `123456789` is `0x29B1`). The full layout, with a
//! page of C for a microcontroller, is in `docs/rig/protocol.md`.
//!
//! **Sensor frame** (rig → controller, 36 bytes, kind `'S'`):
//!
//! | offset | type | field |
//! |---|---|---|
//! | 0 | `u8[2]` | magic `'P' 'L'` |
//! | 2 | `u8` | protocol version (1) |
//! | 3 | `u8` | kind `'S'` (0x53) |
//! | 4 | `u32` | session of the controller whose commands the rig follows (0: none) |
//! | 8 | `u32` | sequence number (+1 per frame sent) |
//! | 12 | `u64` | rig clock, µs since the rig started |
//! | 20 | `i32` | encoder 0 counts (cart `z` / arm `θ₁`) |
//! | 24 | `i32` | encoder 1 counts (pendulum `θ` / `θ₂`) |
//! | 28 | `u32` | sequence number of the last command applied |
//! | 32 | `u16` | status bits ([`status`]) |
//! | 34 | `u16` | CRC over bytes 0..34 |
//!
//! **Command frame** (controller → rig, 24 bytes, kind `'C'`):
//!
//! | offset | type | field |
//! |---|---|---|
//! | 0 | `u8[2]` | magic `'P' 'L'` |
//! | 2 | `u8` | protocol version (1) |
//! | 3 | `u8` | kind `'C'` (0x43) |
//! | 4 | `u32` | session (random, non-zero, fixed for one controller run) |
//! | 8 | `u32` | sequence number (+1 per frame sent) |
//! | 12 | `i32` | motor voltage in µV |
//! | 16 | `u16` | flags ([`flags`]) |
//! | 18 | `u32` | sequence number of the newest sensor frame the command was computed from |
//! | 22 | `u16` | CRC over bytes 0..22 |
//!
//! **Acceptance rules** ([`SequenceGate`]): a receiver acts on a frame only if it has the exact
//! length, the magic, version and kind, a correct checksum, and a sequence number newer than
//! every frame accepted before in the same session (serial-number arithmetic modulo 2³²,
//! RFC 1982: `0 < seq − last < 2³¹`). Equal numbers are *replays*, older ones *out of order*;
//! both are counted and dropped, never acted on. A forward jump of more than
//! [`SequenceGate::MAX_JUMP`] is a *jump*: dropped and counted too, unless the next frame
//! judged follows it closely (within [`SequenceGate::CONFIRM_WINDOW`]), which confirms it — so
//! one wild frame (a sequence number `2³¹ − 1` ahead) cannot capture the gate and make every
//! later good frame "out of order", while a sender that really jumped is followed after one
//! frame.

use std::fmt;

/// Protocol version carried in every frame.
pub const VERSION: u8 = 1;
/// The two magic bytes opening every frame.
pub const MAGIC: [u8; 2] = *b"PL";
/// Frame kind byte of a sensor frame.
pub const KIND_SENSOR: u8 = b'S';
/// Frame kind byte of a command frame.
pub const KIND_COMMAND: u8 = b'C';
/// Length of a sensor frame in bytes.
pub const SENSOR_LEN: usize = 36;
/// Length of a command frame in bytes.
pub const COMMAND_LEN: usize = 24;

/// Status bits of a sensor frame.
pub mod status {
    /// The motor amplifier is enabled (a fresh command with [`super::flags::ENABLE`] is held).
    pub const ENABLED: u16 = 1 << 0;
    /// The rig's watchdog expired (no fresh command in time) and zeroed the motor.
    pub const WATCHDOG: u16 = 1 << 1;
    /// The last command was clipped by the amplifier's saturation.
    pub const SATURATED: u16 = 1 << 2;
    /// The rig's own travel limit switch is hit (the motor is held at 0 V).
    pub const LIMIT: u16 = 1 << 3;
    /// The rig rejected at least one bad frame since the previous sensor frame.
    pub const BAD_FRAME: u16 = 1 << 4;
}

/// Flag bits of a command frame.
pub mod flags {
    /// Drive the motor with the voltage of the frame; without it the rig outputs 0 V.
    pub const ENABLE: u16 = 1 << 0;
    /// The controller stops: the rig zeroes the motor and frees the session at once.
    pub const STOP: u16 = 1 << 1;
}

/// CRC-16/CCITT-FALSE (poly `0x1021`, init `0xFFFF`, MSB first, no final XOR), bitwise: the
/// form a microcontroller implements in eight lines.
pub fn crc16(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &b in bytes {
        crc ^= (b as u16) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// Why a datagram is not a valid frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameError {
    /// Shorter than the frame (`got` bytes of `want`).
    Truncated {
        /// Bytes received.
        got: usize,
        /// Bytes of the frame kind.
        want: usize,
    },
    /// Longer than the frame.
    TooLong {
        /// Bytes received.
        got: usize,
        /// Bytes of the frame kind.
        want: usize,
    },
    /// The first two bytes are not `'P' 'L'`.
    BadMagic,
    /// Another protocol version.
    BadVersion(u8),
    /// Not the expected frame kind.
    BadKind(u8),
    /// The checksum does not match.
    BadChecksum {
        /// CRC carried by the frame.
        carried: u16,
        /// CRC computed over its bytes.
        computed: u16,
    },
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FrameError::Truncated { got, want } => {
                write!(f, "truncated frame: {got} bytes, expected {want}")
            }
            FrameError::TooLong { got, want } => {
                write!(f, "oversized frame: {got} bytes, expected {want}")
            }
            FrameError::BadMagic => write!(f, "bad magic bytes (expected 'PL')"),
            FrameError::BadVersion(v) => {
                write!(f, "protocol version {v}, this build speaks {VERSION}")
            }
            FrameError::BadKind(k) => write!(f, "unexpected frame kind 0x{k:02x}"),
            FrameError::BadChecksum { carried, computed } => write!(
                f,
                "checksum mismatch: frame carries 0x{carried:04x}, bytes give 0x{computed:04x}"
            ),
        }
    }
}

impl std::error::Error for FrameError {}

/// Checks length, magic, version, kind and checksum of a datagram.
fn check(buf: &[u8], want: usize, kind: u8) -> Result<(), FrameError> {
    if buf.len() < want {
        return Err(FrameError::Truncated {
            got: buf.len(),
            want,
        });
    }
    if buf.len() > want {
        return Err(FrameError::TooLong {
            got: buf.len(),
            want,
        });
    }
    if buf[0..2] != MAGIC {
        return Err(FrameError::BadMagic);
    }
    if buf[2] != VERSION {
        return Err(FrameError::BadVersion(buf[2]));
    }
    if buf[3] != kind {
        return Err(FrameError::BadKind(buf[3]));
    }
    let carried = u16::from_le_bytes([buf[want - 2], buf[want - 1]]);
    let computed = crc16(&buf[..want - 2]);
    if carried != computed {
        return Err(FrameError::BadChecksum { carried, computed });
    }
    Ok(())
}

fn u32_at(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}
fn i32_at(b: &[u8], i: usize) -> i32 {
    i32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}
fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

/// A sensor frame (rig → controller).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SensorFrame {
    /// Session of the controller the rig follows (0: none yet).
    pub session: u32,
    /// Sequence number.
    pub seq: u32,
    /// Rig clock \[µs\].
    pub time_us: u64,
    /// Encoder counts (`[z, θ]` on the cart rig, `[θ₁, θ₂]` on the arm rig).
    pub counts: [i32; 2],
    /// Sequence number of the last command applied (0: none).
    pub command_seq: u32,
    /// [`status`] bits.
    pub status: u16,
}

impl SensorFrame {
    /// Serialises the frame with its checksum.
    pub fn encode(&self) -> [u8; SENSOR_LEN] {
        let mut b = [0u8; SENSOR_LEN];
        b[0..2].copy_from_slice(&MAGIC);
        b[2] = VERSION;
        b[3] = KIND_SENSOR;
        b[4..8].copy_from_slice(&self.session.to_le_bytes());
        b[8..12].copy_from_slice(&self.seq.to_le_bytes());
        b[12..20].copy_from_slice(&self.time_us.to_le_bytes());
        b[20..24].copy_from_slice(&self.counts[0].to_le_bytes());
        b[24..28].copy_from_slice(&self.counts[1].to_le_bytes());
        b[28..32].copy_from_slice(&self.command_seq.to_le_bytes());
        b[32..34].copy_from_slice(&self.status.to_le_bytes());
        let crc = crc16(&b[..SENSOR_LEN - 2]);
        b[34..36].copy_from_slice(&crc.to_le_bytes());
        b
    }

    /// Parses and checks a datagram.
    ///
    /// # Errors
    /// [`FrameError`] naming what is wrong.
    pub fn decode(buf: &[u8]) -> Result<Self, FrameError> {
        check(buf, SENSOR_LEN, KIND_SENSOR)?;
        Ok(Self {
            session: u32_at(buf, 4),
            seq: u32_at(buf, 8),
            time_us: u64::from_le_bytes(buf[12..20].try_into().expect("8 bytes")),
            counts: [i32_at(buf, 20), i32_at(buf, 24)],
            command_seq: u32_at(buf, 28),
            status: u16_at(buf, 32),
        })
    }
}

/// A command frame (controller → rig).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CommandFrame {
    /// Session of the controller run (non-zero).
    pub session: u32,
    /// Sequence number.
    pub seq: u32,
    /// Motor voltage \[µV\].
    pub microvolts: i32,
    /// [`flags`] bits.
    pub flags: u16,
    /// Sequence number of the sensor frame the command was computed from.
    pub sensor_seq: u32,
}

impl CommandFrame {
    /// The voltage in volts.
    pub fn volts(&self) -> f64 {
        self.microvolts as f64 * 1e-6
    }

    /// Converts volts to the frame's µV, rounding to the nearest and saturating at the `i32`
    /// range (±2147 V); a non-finite voltage becomes 0.
    pub fn microvolts_of(volts: f64) -> i32 {
        if !volts.is_finite() {
            return 0;
        }
        (volts * 1e6)
            .round()
            .clamp(i32::MIN as f64, i32::MAX as f64) as i32
    }

    /// Serialises the frame with its checksum.
    pub fn encode(&self) -> [u8; COMMAND_LEN] {
        let mut b = [0u8; COMMAND_LEN];
        b[0..2].copy_from_slice(&MAGIC);
        b[2] = VERSION;
        b[3] = KIND_COMMAND;
        b[4..8].copy_from_slice(&self.session.to_le_bytes());
        b[8..12].copy_from_slice(&self.seq.to_le_bytes());
        b[12..16].copy_from_slice(&self.microvolts.to_le_bytes());
        b[16..18].copy_from_slice(&self.flags.to_le_bytes());
        b[18..22].copy_from_slice(&self.sensor_seq.to_le_bytes());
        let crc = crc16(&b[..COMMAND_LEN - 2]);
        b[22..24].copy_from_slice(&crc.to_le_bytes());
        b
    }

    /// Parses and checks a datagram.
    ///
    /// # Errors
    /// [`FrameError`] naming what is wrong.
    pub fn decode(buf: &[u8]) -> Result<Self, FrameError> {
        check(buf, COMMAND_LEN, KIND_COMMAND)?;
        Ok(Self {
            session: u32_at(buf, 4),
            seq: u32_at(buf, 8),
            microvolts: i32_at(buf, 12),
            flags: u16_at(buf, 16),
            sensor_seq: u32_at(buf, 18),
        })
    }
}

/// What the [`SequenceGate`] says about a sequence number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeqVerdict {
    /// Newer than everything accepted before: act on it. `skipped` frames were never seen
    /// (lost, or still to arrive late and be rejected).
    Fresh {
        /// Sequence numbers jumped over.
        skipped: u32,
    },
    /// The same number as the last accepted frame.
    Replayed,
    /// Older than the last accepted frame.
    OutOfOrder,
    /// More than [`SequenceGate::MAX_JUMP`] ahead of the last accepted frame and not (yet)
    /// confirmed by a following frame: dropped.
    Jump,
}

/// Serial-number acceptance of one stream (RFC 1982 arithmetic modulo 2³²), with far forward
/// jumps held until confirmed.
///
/// With `last` the last accepted number and `d = seq − last (mod 2³²)`:
/// `d = 0` replayed; `0 < d ≤ MAX_JUMP` fresh; `d ≥ 2³¹` out of order; otherwise a jump,
/// which becomes the gate's *candidate*: it is accepted (fresh) only if the next far frame
/// judged is `1..=CONFIRM_WINDOW` after the candidate (the sender really jumped); an in-range
/// fresh frame in between drops the candidate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SequenceGate {
    last: Option<u32>,
    candidate: Option<u32>,
}

impl SequenceGate {
    /// The largest forward jump accepted without confirmation: 16 frames. A wild number that
    /// slips through (up to 16 ahead) makes at most 16 following good frames look old, fewer
    /// than the runtime's default stale hold of 20 periods, so the loop bridges it by holding
    /// its command instead of losing the run; a real loss of more frames costs one frame, the
    /// one whose successor confirms the jump.
    pub const MAX_JUMP: u32 = 16;
    /// A far jump is confirmed by a next far frame at most this far after it.
    pub const CONFIRM_WINDOW: u32 = 16;

    /// A gate that has accepted nothing yet (the first frame is always fresh).
    pub fn new() -> Self {
        Self::default()
    }

    /// Judges `seq` and, if fresh, records it.
    pub fn check(&mut self, seq: u32) -> SeqVerdict {
        let Some(last) = self.last else {
            self.last = Some(seq);
            return SeqVerdict::Fresh { skipped: 0 };
        };
        let d = seq.wrapping_sub(last);
        if d == 0 {
            SeqVerdict::Replayed
        } else if d <= Self::MAX_JUMP {
            self.last = Some(seq);
            self.candidate = None;
            SeqVerdict::Fresh { skipped: d - 1 }
        } else if d >= 1 << 31 {
            SeqVerdict::OutOfOrder
        } else {
            match self.candidate {
                Some(c) if (1..=Self::CONFIRM_WINDOW).contains(&seq.wrapping_sub(c)) => {
                    self.last = Some(seq);
                    self.candidate = None;
                    SeqVerdict::Fresh { skipped: d - 1 }
                }
                _ => {
                    self.candidate = Some(seq);
                    SeqVerdict::Jump
                }
            }
        }
    }

    /// The last accepted sequence number.
    pub fn last(&self) -> Option<u32> {
        self.last
    }

    /// Forgets the stream (a new session starts).
    pub fn reset(&mut self) {
        self.last = None;
        self.candidate = None;
    }
}

/// Counters of rejected frames, by reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RejectCounts {
    /// Too short.
    pub truncated: u64,
    /// Too long, bad magic, version or kind.
    pub malformed: u64,
    /// Checksum mismatch.
    pub checksum: u64,
    /// Same sequence number as the last accepted frame.
    pub replayed: u64,
    /// Older sequence number.
    pub out_of_order: u64,
    /// From another session than the one being served.
    pub foreign_session: u64,
    /// Sequence number too far ahead and not confirmed ([`SeqVerdict::Jump`]).
    pub jump: u64,
}

impl RejectCounts {
    /// Counts a framing error.
    pub fn count_error(&mut self, e: FrameError) {
        match e {
            FrameError::Truncated { .. } => self.truncated += 1,
            FrameError::BadChecksum { .. } => self.checksum += 1,
            _ => self.malformed += 1,
        }
    }

    /// Counts a sequence verdict (fresh frames are not counted).
    pub fn count_verdict(&mut self, v: SeqVerdict) {
        match v {
            SeqVerdict::Replayed => self.replayed += 1,
            SeqVerdict::OutOfOrder => self.out_of_order += 1,
            SeqVerdict::Jump => self.jump += 1,
            SeqVerdict::Fresh { .. } => {}
        }
    }

    /// All rejections.
    pub fn total(&self) -> u64 {
        self.truncated
            + self.malformed
            + self.checksum
            + self.replayed
            + self.out_of_order
            + self.foreign_session
            + self.jump
    }
}

impl fmt::Display for RejectCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "truncated {}, malformed {}, checksum {}, replayed {}, out-of-order {}, foreign session {}, unconfirmed jump {}",
            self.truncated,
            self.malformed,
            self.checksum,
            self.replayed,
            self.out_of_order,
            self.foreign_session,
            self.jump
        )
    }
}

/// Frames out of a byte stream (a serial line has no datagram boundaries).
///
/// Bytes are appended with [`StreamDecoder::push`]; [`StreamDecoder::next_frame`] returns
/// the next `len`-byte window that starts with the magic, version and `kind` and carries a
/// correct checksum. After garbage or a corrupted frame it drops one byte and searches again
/// (resynchronisation), counting the dropped bytes.
#[derive(Debug, Clone, Default)]
pub struct StreamDecoder {
    buf: Vec<u8>,
    /// Bytes discarded while resynchronising.
    pub skipped: u64,
}

impl StreamDecoder {
    /// An empty decoder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// The next valid frame of `len` bytes and kind `kind`, if one is complete.
    pub fn next_frame(&mut self, len: usize, kind: u8) -> Option<Vec<u8>> {
        loop {
            if self.buf.len() < len {
                return None;
            }
            if check(&self.buf[..len], len, kind).is_ok() {
                let frame = self.buf[..len].to_vec();
                self.buf.drain(..len);
                return Some(frame);
            }
            self.buf.remove(0);
            self.skipped += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensor() -> SensorFrame {
        SensorFrame {
            session: 0xDEAD_BEEF,
            seq: 41,
            time_us: 1_234_567_890_123,
            counts: [-12345, 7200],
            command_seq: 40,
            status: status::ENABLED | status::SATURATED,
        }
    }

    fn command() -> CommandFrame {
        CommandFrame {
            session: 7,
            seq: 3,
            microvolts: -4_999_847,
            flags: flags::ENABLE,
            sensor_seq: 99,
        }
    }

    #[test]
    fn crc_matches_the_catalogue_check_value() {
        // CRC-16/CCITT-FALSE check value of "123456789" from the CRC catalogue (Greg Cook,
        // "Catalogue of parametrised CRC algorithms", entry CRC-16/IBM-3740): 0x29B1.
        assert_eq!(crc16(b"123456789"), 0x29B1);
        // Empty input leaves the initial value.
        assert_eq!(crc16(b""), 0xFFFF);
    }

    #[test]
    fn frames_round_trip_with_their_documented_layout() {
        let s = sensor();
        let b = s.encode();
        assert_eq!(b.len(), SENSOR_LEN);
        assert_eq!(&b[0..4], b"PL\x01S");
        // Field offsets as documented: seq at 8, encoder 1 at 24, status at 32.
        assert_eq!(u32::from_le_bytes(b[8..12].try_into().unwrap()), 41);
        assert_eq!(i32::from_le_bytes(b[24..28].try_into().unwrap()), 7200);
        assert_eq!(u16::from_le_bytes(b[32..34].try_into().unwrap()), 0b101);
        assert_eq!(SensorFrame::decode(&b), Ok(s));

        let c = command();
        let b = c.encode();
        assert_eq!(b.len(), COMMAND_LEN);
        assert_eq!(&b[0..4], b"PL\x01C");
        assert_eq!(
            i32::from_le_bytes(b[12..16].try_into().unwrap()),
            -4_999_847
        );
        assert_eq!(CommandFrame::decode(&b), Ok(c));
        assert!((c.volts() + 4.999847).abs() < 1e-12);
    }

    #[test]
    fn every_single_bit_flip_is_rejected() {
        // A CRC with a generator of ≥ 2 terms detects every single-bit error; each flip must
        // give a framing error, never a frame.
        let b = sensor().encode();
        for i in 0..SENSOR_LEN * 8 {
            let mut m = b;
            m[i / 8] ^= 1 << (i % 8);
            assert!(SensorFrame::decode(&m).is_err(), "bit {i} flipped");
        }
        let b = command().encode();
        for i in 0..COMMAND_LEN * 8 {
            let mut m = b;
            m[i / 8] ^= 1 << (i % 8);
            assert!(CommandFrame::decode(&m).is_err(), "bit {i} flipped");
        }
    }

    #[test]
    fn malformed_and_truncated_frames_are_typed_errors() {
        let b = command().encode();
        for n in 0..COMMAND_LEN {
            assert_eq!(
                CommandFrame::decode(&b[..n]),
                Err(FrameError::Truncated {
                    got: n,
                    want: COMMAND_LEN
                })
            );
        }
        let mut long = b.to_vec();
        long.push(0);
        assert!(matches!(
            CommandFrame::decode(&long),
            Err(FrameError::TooLong { .. })
        ));
        // A sensor frame is not a command (length differs), and a command-length datagram
        // with the sensor kind byte is the wrong kind.
        assert!(CommandFrame::decode(&sensor().encode()).is_err());
        let mut k = b;
        k[3] = KIND_SENSOR;
        let crc = crc16(&k[..COMMAND_LEN - 2]);
        k[22..24].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(
            CommandFrame::decode(&k),
            Err(FrameError::BadKind(KIND_SENSOR))
        );
        let mut v = b;
        v[2] = 2;
        assert_eq!(CommandFrame::decode(&v), Err(FrameError::BadVersion(2)));
        let mut m = b;
        m[0] = b'X';
        assert_eq!(CommandFrame::decode(&m), Err(FrameError::BadMagic));
        let mut c = b;
        c[23] ^= 0xFF;
        assert!(matches!(
            CommandFrame::decode(&c),
            Err(FrameError::BadChecksum { .. })
        ));
        let mut counts = RejectCounts::default();
        for e in [
            FrameError::Truncated { got: 1, want: 24 },
            FrameError::BadMagic,
            FrameError::BadChecksum {
                carried: 0,
                computed: 1,
            },
        ] {
            counts.count_error(e);
            assert!(!e.to_string().is_empty());
        }
        assert_eq!(
            (counts.truncated, counts.malformed, counts.checksum),
            (1, 1, 1)
        );
    }

    #[test]
    fn sequence_gate_rejects_replayed_and_out_of_order_frames() {
        let mut g = SequenceGate::new();
        assert_eq!(g.check(10), SeqVerdict::Fresh { skipped: 0 });
        assert_eq!(g.check(11), SeqVerdict::Fresh { skipped: 0 });
        assert_eq!(g.check(11), SeqVerdict::Replayed);
        assert_eq!(g.check(14), SeqVerdict::Fresh { skipped: 2 });
        // 12 and 13 arriving late are out of order, and do not move the gate back.
        assert_eq!(g.check(12), SeqVerdict::OutOfOrder);
        assert_eq!(g.check(13), SeqVerdict::OutOfOrder);
        assert_eq!(g.last(), Some(14));
        assert_eq!(g.check(15), SeqVerdict::Fresh { skipped: 0 });
        // Wrap-around modulo 2³²: u32::MAX then 0 is in order, 0 then u32::MAX is not.
        let mut w = SequenceGate::new();
        w.check(u32::MAX);
        assert_eq!(w.check(0), SeqVerdict::Fresh { skipped: 0 });
        assert_eq!(w.check(u32::MAX), SeqVerdict::OutOfOrder);
        w.reset();
        assert_eq!(w.check(5), SeqVerdict::Fresh { skipped: 0 });
    }

    #[test]
    fn one_wild_frame_does_not_capture_the_gate() {
        // Good frames 100, 101; a wild one 2³¹ − 1 ahead; the good stream goes on.
        let mut g = SequenceGate::new();
        g.check(100);
        g.check(101);
        let wild = 101u32.wrapping_add((1 << 31) - 1);
        assert_eq!(g.check(wild), SeqVerdict::Jump);
        for seq in 102..110 {
            assert_eq!(g.check(seq), SeqVerdict::Fresh { skipped: 0 }, "{seq}");
        }
        // The wild number was dropped with the candidate: it stays a jump.
        assert_eq!(g.check(wild.wrapping_add(1)), SeqVerdict::Jump);
        // The edge: MAX_JUMP ahead is fresh, one more is a jump.
        let mut e = SequenceGate::new();
        e.check(0);
        assert_eq!(
            e.check(SequenceGate::MAX_JUMP),
            SeqVerdict::Fresh {
                skipped: SequenceGate::MAX_JUMP - 1
            }
        );
        let far = 2 * SequenceGate::MAX_JUMP + 1;
        assert_eq!(e.check(far), SeqVerdict::Jump);
        // A wild number within MAX_JUMP is taken, and costs exactly the good frames it
        // overtook: at most MAX_JUMP of them, fewer than the runtime's default stale hold.
        let mut w = SequenceGate::new();
        w.check(500);
        let m = SequenceGate::MAX_JUMP;
        assert!(matches!(w.check(500 + m), SeqVerdict::Fresh { .. }));
        let lost = (501..=500 + 2 * m)
            .filter(|&q| !matches!(w.check(q), SeqVerdict::Fresh { .. }))
            .count();
        assert_eq!(lost as u32, m);
        assert!(m < crate::runtime::Safety::default_for(crate::PlantKind::Cart).stale_hold_periods);
        let mut c = RejectCounts::default();
        c.count_verdict(SeqVerdict::Jump);
        assert_eq!(c.jump, 1);
    }

    #[test]
    fn a_real_jump_is_confirmed_by_the_next_frame() {
        // A sender that restarted its numbering a million ahead: the first frame is held,
        // the second (two later: one lost in between) confirms the jump.
        let mut g = SequenceGate::new();
        g.check(7);
        assert_eq!(g.check(1_000_000), SeqVerdict::Jump);
        assert_eq!(
            g.check(1_000_002),
            SeqVerdict::Fresh {
                skipped: 1_000_002 - 7 - 1
            }
        );
        assert_eq!(g.last(), Some(1_000_002));
        assert_eq!(g.check(1_000_003), SeqVerdict::Fresh { skipped: 0 });
        // Two far frames that do not follow one another confirm nothing.
        let mut h = SequenceGate::new();
        h.check(7);
        assert_eq!(h.check(1_000_000), SeqVerdict::Jump);
        assert_eq!(
            h.check(1_000_000 + SequenceGate::CONFIRM_WINDOW + 1),
            SeqVerdict::Jump
        );
    }

    #[test]
    fn stream_decoder_resynchronises_after_garbage_and_corruption() {
        let a = sensor().encode();
        let b = SensorFrame {
            seq: 42,
            ..sensor()
        }
        .encode();
        let mut corrupt = SensorFrame {
            seq: 43,
            ..sensor()
        }
        .encode();
        corrupt[10] ^= 4;
        let mut d = StreamDecoder::new();
        d.push(b"\x00PLjunk");
        d.push(&a[..10]);
        assert_eq!(d.next_frame(SENSOR_LEN, KIND_SENSOR), None);
        d.push(&a[10..]);
        d.push(&corrupt);
        d.push(&b);
        let f1 = d.next_frame(SENSOR_LEN, KIND_SENSOR).unwrap();
        let f2 = d.next_frame(SENSOR_LEN, KIND_SENSOR).unwrap();
        assert_eq!(SensorFrame::decode(&f1).unwrap().seq, 41);
        assert_eq!(SensorFrame::decode(&f2).unwrap().seq, 42);
        assert_eq!(d.next_frame(SENSOR_LEN, KIND_SENSOR), None);
        // 7 garbage bytes before the first frame, the whole corrupted frame after it.
        assert_eq!(d.skipped, 7 + SENSOR_LEN as u64);
    }

    #[test]
    fn microvolt_conversion_saturates_and_guards_nan() {
        assert_eq!(CommandFrame::microvolts_of(1.5), 1_500_000);
        assert_eq!(CommandFrame::microvolts_of(-0.0000004), 0);
        assert_eq!(CommandFrame::microvolts_of(f64::NAN), 0);
        assert_eq!(CommandFrame::microvolts_of(1e9), i32::MAX);
        assert_eq!(CommandFrame::microvolts_of(f64::NEG_INFINITY), 0);
    }
}
