//! Fuzz target `protocol`: the rig's wire-protocol decoders and sequence gate
//! (`pendulab_rig::protocol`), against the frame layout of `docs/rig/protocol.md`.
//!
//! Properties:
//! - any datagram (random, or a valid frame mutated by bit flips, truncation, extension,
//!   deletion, duplication) decodes without panicking, and a decoded frame re-encodes to the
//!   same bytes;
//! - a datagram of the right length, header and a correct CRC decodes whatever its payload,
//!   to the fields at the offsets of the protocol's tables (read here independently);
//! - one, two or three flipped bits of a valid frame are always rejected (CRC-16/CCITT's
//!   polynomial 0x1021 has Hamming distance 4 for codewords up to 32 767 bits, Koopman's CRC
//!   tables; a frame is 288 bits);
//! - the sequence gate never panics, accepts a stream advancing by 1..=k (across the 2³²
//!   wrap) with `skipped = k − 1`, calls a repeat of the last accepted number a replay, and
//!   never accepts a number up to 2¹⁶ behind the last accepted one.

use pendulab_fuzz::{Target, cases, mutate, mutations};
use pendulab_rig::protocol::{
    COMMAND_LEN, CommandFrame, FrameError, KIND_COMMAND, KIND_SENSOR, MAGIC, SENSOR_LEN,
    SensorFrame, SeqVerdict, SequenceGate, VERSION, crc16,
};
use proptest::prelude::*;

const TARGET: Target = Target {
    name: "protocol",
    extension: "bin",
};

/// Sequence-gate reproducers: the sequence numbers judged, in order, as decimal text.
const GATE: Target = Target {
    name: "sequence_gate",
    extension: "txt",
};

/// A gate reproducer as text: the property's name on the first line, then its numbers.
fn gate_file(property: &str, numbers: &[u32]) -> Vec<u8> {
    let mut text = format!("{property}\n");
    for q in numbers {
        text.push_str(&format!("{q}\n"));
    }
    text.into_bytes()
}

/// Replays a gate reproducer written by [`gate_file`].
fn gate_replay(bytes: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(bytes);
    let mut words = text.split_whitespace();
    let property = words.next().unwrap_or("");
    let n: Vec<u32> = words
        .map(str::parse::<u32>)
        .collect::<Result<_, _>>()
        .map_err(|e| format!("not a list of u32: {e}"))?;
    match (property, &n[..]) {
        ("any", seqs) => gate_invariant(seqs),
        ("advancing", [start, rest @ ..]) if rest.len() % 2 == 0 => {
            let steps: Vec<(u32, u32)> = rest.chunks(2).map(|c| (c[0], c[1])).collect();
            advancing(*start, &steps)
        }
        ("wild", &[start, before, wild]) => wild_frame(start, before, wild),
        _ => Err(format!("unknown gate reproducer {property:?} {n:?}")),
    }
}

/// The gate's invariant on any stream: it never panics, and a number judged fresh becomes
/// `last()`.
fn gate_invariant(seqs: &[u32]) -> Result<(), String> {
    let mut gate = SequenceGate::new();
    for &q in seqs {
        let v = gate.check(q);
        if matches!(v, SeqVerdict::Fresh { .. }) && gate.last() != Some(q) {
            return Err(format!("{q} accepted but last() = {:?}", gate.last()));
        }
    }
    Ok(())
}

/// Tokens for binary mutation: the header bytes of both frame kinds and extreme integers.
const BIN_TOKENS: &[&str] = &[
    "PL",
    "PL\u{1}S",
    "PL\u{1}C",
    "\u{0}\u{0}\u{0}\u{0}",
    "\u{7f}\u{7f}\u{7f}\u{7f}",
];

fn u32_le(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes(b[i..i + 4].try_into().unwrap())
}

/// Decodes `bytes` as both frame kinds. A decoded frame must re-encode to `bytes` and carry
/// the fields at the offsets of `docs/rig/protocol.md`; a rejection must be for a reason
/// that holds.
fn decode_both(bytes: &[u8]) -> Result<(), String> {
    match SensorFrame::decode(bytes) {
        Ok(f) => {
            if f.encode()[..] != *bytes {
                return Err(format!("sensor frame {f:?} re-encodes differently"));
            }
            let want = SensorFrame {
                session: u32_le(bytes, 4),
                seq: u32_le(bytes, 8),
                time_us: u64::from_le_bytes(bytes[12..20].try_into().unwrap()),
                counts: [u32_le(bytes, 20) as i32, u32_le(bytes, 24) as i32],
                command_seq: u32_le(bytes, 28),
                status: u16::from_le_bytes([bytes[32], bytes[33]]),
            };
            if f != want {
                return Err(format!("decoded {f:?}, the layout gives {want:?}"));
            }
        }
        Err(e) => check_rejection(bytes, SENSOR_LEN, KIND_SENSOR, e)?,
    }
    match CommandFrame::decode(bytes) {
        Ok(f) => {
            if f.encode()[..] != *bytes {
                return Err(format!("command frame {f:?} re-encodes differently"));
            }
            let want = CommandFrame {
                session: u32_le(bytes, 4),
                seq: u32_le(bytes, 8),
                microvolts: u32_le(bytes, 12) as i32,
                flags: u16::from_le_bytes([bytes[16], bytes[17]]),
                sensor_seq: u32_le(bytes, 18),
            };
            if f != want {
                return Err(format!("decoded {f:?}, the layout gives {want:?}"));
            }
        }
        Err(e) => check_rejection(bytes, COMMAND_LEN, KIND_COMMAND, e)?,
    }
    Ok(())
}

/// A rejection names a defect the datagram has (checked in the protocol's order: length,
/// magic, version, kind, checksum) and prints a non-empty message.
fn check_rejection(b: &[u8], len: usize, kind: u8, e: FrameError) -> Result<(), String> {
    if e.to_string().is_empty() {
        return Err(format!("{e:?} prints an empty message"));
    }
    let ok = match e {
        FrameError::Truncated { got, want } => got == b.len() && want == len && got < want,
        FrameError::TooLong { got, want } => got == b.len() && want == len && got > want,
        FrameError::BadMagic => b.len() == len && b[0..2] != MAGIC,
        FrameError::BadVersion(v) => {
            b.len() == len && b[0..2] == MAGIC && v == b[2] && v != VERSION
        }
        FrameError::BadKind(k) => {
            b.len() == len && b[0..2] == MAGIC && b[2] == VERSION && k == b[3] && k != kind
        }
        FrameError::BadChecksum { carried, computed } => {
            b.len() == len
                && b[0..4] == [MAGIC[0], MAGIC[1], VERSION, kind]
                && carried == u16::from_le_bytes([b[len - 2], b[len - 1]])
                && computed == crc16(&b[..len - 2])
                && carried != computed
        }
    };
    if ok {
        Ok(())
    } else {
        Err(format!(
            "rejected as {e:?}, which does not describe {b:02x?}"
        ))
    }
}

fn sensor_frame() -> impl Strategy<Value = SensorFrame> {
    (
        any::<u32>(),
        any::<u32>(),
        any::<u64>(),
        any::<[i32; 2]>(),
        any::<u32>(),
        any::<u16>(),
    )
        .prop_map(
            |(session, seq, time_us, counts, command_seq, status)| SensorFrame {
                session,
                seq,
                time_us,
                counts,
                command_seq,
                status,
            },
        )
}

fn command_frame() -> impl Strategy<Value = CommandFrame> {
    (
        any::<u32>(),
        any::<u32>(),
        any::<i32>(),
        any::<u16>(),
        any::<u32>(),
    )
        .prop_map(
            |(session, seq, microvolts, flags, sensor_seq)| CommandFrame {
                session,
                seq,
                microvolts,
                flags,
                sensor_seq,
            },
        )
}

/// A valid encoded frame of either kind.
fn valid_frame() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        sensor_frame().prop_map(|f| f.encode().to_vec()),
        command_frame().prop_map(|f| f.encode().to_vec()),
    ]
}

#[test]
fn crc_is_the_documented_ccitt_false() {
    // docs/rig/protocol.md: check value of the ASCII bytes "123456789".
    assert_eq!(crc16(b"123456789"), 0x29B1);
}

#[test]
fn random_datagrams() {
    TARGET.run(
        cases(48000),
        proptest::collection::vec(any::<u8>(), 0..80),
        |b| b.clone(),
        |b| decode_both(b),
    );
}

#[test]
fn mutated_valid_frames() {
    TARGET.run(
        cases(72000),
        (valid_frame(), mutations(BIN_TOKENS, 1, 6)),
        |(f, m)| mutate(f, m),
        |(f, m)| decode_both(&mutate(f, m)),
    );
}

#[test]
fn crc_correct_garbage_decodes_to_its_fields() {
    let garbage = (
        any::<bool>(),
        proptest::collection::vec(any::<u8>(), SENSOR_LEN),
    )
        .prop_map(|(sensor, mut b)| {
            let (len, kind) = if sensor {
                (SENSOR_LEN, KIND_SENSOR)
            } else {
                (COMMAND_LEN, KIND_COMMAND)
            };
            b.truncate(len);
            b[..4].copy_from_slice(&[MAGIC[0], MAGIC[1], VERSION, kind]);
            let crc = crc16(&b[..len - 2]);
            b[len - 2..].copy_from_slice(&crc.to_le_bytes());
            b
        });
    TARGET.run(
        cases(48000),
        garbage,
        |b| b.clone(),
        |b| {
            let decoded = if b.len() == SENSOR_LEN {
                SensorFrame::decode(b).map(|_| ())
            } else {
                CommandFrame::decode(b).map(|_| ())
            };
            decoded.map_err(|e| format!("a frame with a correct CRC rejected: {e}"))?;
            decode_both(b)
        },
    );
}

#[test]
fn up_to_three_flipped_bits_are_always_rejected() {
    let flips = proptest::collection::btree_set(any::<usize>(), 1..=3);
    TARGET.run(
        cases(72000),
        (valid_frame(), flips),
        |(f, _)| f.clone(),
        |(f, flips)| {
            let mut b = f.clone();
            let bits = b.len() * 8;
            let positions: std::collections::BTreeSet<usize> =
                flips.iter().map(|p| p % bits).collect();
            for p in &positions {
                b[p / 8] ^= 1 << (p % 8);
            }
            let accepted = if b.len() == SENSOR_LEN {
                SensorFrame::decode(&b).is_ok()
            } else {
                CommandFrame::decode(&b).is_ok()
            };
            if accepted {
                return Err(format!("bits {positions:?} flipped and still accepted"));
            }
            Ok(())
        },
    );
}

/// The advancing-stream property: from `start`, per step a repeat of the last accepted
/// number (a replay), a number `back` behind it (never fresh) and one `advance` ahead: fresh
/// (`advance − 1` skipped) up to [`SequenceGate::MAX_JUMP`]; beyond, held as a jump and
/// accepted with the frame right after it (`advance` skipped), which confirms it.
fn advancing(start: u32, steps: &[(u32, u32)]) -> Result<(), String> {
    let mut gate = SequenceGate::new();
    if gate.check(start) != (SeqVerdict::Fresh { skipped: 0 }) {
        return Err("the first frame is not fresh".into());
    }
    let mut last = start;
    for &(advance, back) in steps {
        if advance == 0 {
            return Err("a reproducer with a zero advance".into());
        }
        // A repeat, and a number `back` behind: never acted on.
        let v = gate.check(last);
        if v != SeqVerdict::Replayed {
            return Err(format!("repeat of {last} judged {v:?}"));
        }
        let old = last.wrapping_sub(back);
        let v = gate.check(old);
        if matches!(v, SeqVerdict::Fresh { .. }) {
            return Err(format!("{old}, {back} behind {last}, judged {v:?}"));
        }
        let mut next = last.wrapping_add(advance);
        let mut skipped = advance - 1;
        if advance > SequenceGate::MAX_JUMP {
            let v = gate.check(next);
            if v != SeqVerdict::Jump {
                return Err(format!("{next}, {advance} ahead of {last}, judged {v:?}"));
            }
            next = next.wrapping_add(1);
            skipped = advance;
        }
        let v = gate.check(next);
        if v != (SeqVerdict::Fresh { skipped }) {
            return Err(format!("{next}, {advance} ahead of {last}, judged {v:?}"));
        }
        if gate.last() != Some(next) {
            return Err(format!("last() = {:?} after accepting {next}", gate.last()));
        }
        last = next;
    }
    Ok(())
}

/// A stream: a start, then per step a repeat of the last accepted number, a number `back`
/// behind it and one `advance` ahead.
#[test]
fn advancing_stream() {
    let stream = (
        any::<u32>(),
        proptest::collection::vec((1u32..=1000, 1u32..=65536), 1..64),
    );
    GATE.run(
        cases(36000),
        stream,
        |(start, steps)| {
            let mut n = vec![*start];
            n.extend(steps.iter().flat_map(|&(a, b)| [a, b]));
            gate_file("advancing", &n)
        },
        |(start, steps)| advancing(*start, steps),
    );
}

/// The wild-frame property: after `before` consecutive frames from `start`, one frame `wild`
/// ahead of the last; the next 32 good frames must all be fresh.
fn wild_frame(start: u32, before: u32, wild: u32) -> Result<(), String> {
    let mut gate = SequenceGate::new();
    for i in 0..before {
        gate.check(start.wrapping_add(i));
    }
    let last = start.wrapping_add(before.max(1) - 1);
    gate.check(last.wrapping_add(wild));
    let rejected = (1..=32)
        .filter(|&i| !matches!(gate.check(last.wrapping_add(i)), SeqVerdict::Fresh { .. }))
        .count();
    if rejected > 0 {
        return Err(format!(
            "after one frame {wild} ahead of {last}, {rejected} of the next 32 good frames were rejected"
        ));
    }
    Ok(())
}

/// Issue 21: one frame far ahead (a corrupted sequence number that still passed the CRC, the
/// issue's case being 2³¹ − 1 ahead) must not capture the gate and make every later good frame
/// "out of order". A jump of up to [`SequenceGate::MAX_JUMP`] is left out: it is
/// indistinguishable from that many lost frames (and costs at most that many good frames).
#[test]
fn a_wild_frame_does_not_capture_the_gate() {
    let case = (
        any::<u32>(),
        1u32..40,
        (SequenceGate::MAX_JUMP + 1)..(1u32 << 31),
        proptest::bool::ANY,
    );
    GATE.run(
        cases(24000),
        case,
        |&(start, before, wild, exact)| {
            let wild = if exact { (1 << 31) - 1 } else { wild };
            gate_file("wild", &[start, before, wild])
        },
        |&(start, before, wild, exact)| {
            let wild = if exact { (1 << 31) - 1 } else { wild };
            wild_frame(start, before, wild)
        },
    );
}

#[test]
fn the_sequence_gate_never_panics_on_any_stream() {
    GATE.run(
        cases(36000),
        proptest::collection::vec(any::<u32>(), 0..64),
        |s| gate_file("any", s),
        |s| gate_invariant(s),
    );
}

#[test]
fn corpus_replays() {
    // Every reproducer of this target is a datagram: decoding it must hold the properties.
    let n = TARGET.replay(&[], decode_both);
    println!("protocol corpus: {n} files replayed");
    let n = GATE.replay(&[], gate_replay);
    println!("sequence_gate corpus: {n} files replayed");
}
