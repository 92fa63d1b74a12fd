//! The page of C in `docs/rig/protocol.md` compiles and follows the protocol's sequence rules.
//!
//! The test extracts the document's C block, compiles it with the system C compiler together
//! with `tests/c/firmware_gate.c` (stubs for the timer, D/A and encoders, and the rule cases:
//! in order, replay, older, foreign session, one wild frame 2³¹ − 1 ahead, a confirmed far
//! jump) and runs it. The expected verdicts are the rules written in the document and
//! implemented by `pendulab_rig::protocol::SequenceGate`, checked against each other here.

use pendulab_rig::protocol::{SeqVerdict, SequenceGate};
use std::path::Path;
use std::process::Command;

fn c_block(doc: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for line in doc.lines() {
        if line.trim_start().starts_with("```c") {
            inside = true;
        } else if inside && line.trim_start().starts_with("```") {
            inside = false;
        } else if inside {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

#[test]
fn the_documented_firmware_compiles_and_follows_the_sequence_rules() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("../../docs/rig/protocol.md")).unwrap();
    let c = c_block(&doc);
    assert!(
        c.contains("void on_command"),
        "no C block with on_command in protocol.md"
    );
    let dir = std::env::temp_dir().join(format!("pendulab-fw-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("fw.c"), c).unwrap();
    std::fs::copy(root.join("tests/c/firmware_gate.c"), dir.join("main.c")).unwrap();
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let out = Command::new(&cc)
        .current_dir(&dir)
        .args(["-std=c99", "-Wall", "-Werror", "-o", "gate", "main.c"])
        .output()
        .unwrap_or_else(|e| panic!("running the C compiler `{cc}`: {e}"));
    assert!(
        out.status.success(),
        "the C of protocol.md does not compile:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = Command::new(dir.join("gate")).output().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stdout)
    );

    // The same cases through the Rust gate: the verdicts the C program asserts.
    let mut g = SequenceGate::default();
    assert!(matches!(g.check(1), SeqVerdict::Fresh { .. }));
    assert!(matches!(g.check(2), SeqVerdict::Fresh { .. }));
    assert!(!matches!(
        g.check(2u32.wrapping_add(0x7FFF_FFFF)),
        SeqVerdict::Fresh { .. }
    ));
    assert!(matches!(g.check(3), SeqVerdict::Fresh { .. }));
    assert_eq!(g.check(3), SeqVerdict::Replayed);
    assert!(!matches!(g.check(100_000), SeqVerdict::Fresh { .. }));
    assert!(matches!(g.check(100_001), SeqVerdict::Fresh { .. }));
    assert_eq!(g.check(5), SeqVerdict::OutOfOrder);
}
