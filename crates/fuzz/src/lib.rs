//! pendulab's fuzz suite: seeded [proptest] generators over the parsers that read what a
//! user, a file or a network peer hands the laboratory, run by plain `cargo test` (no nightly
//! compiler, no `cargo-fuzz`), with a corpus of every reproducer found.
//!
//! The targets are the test files of this crate (`tests/*.rs`), one per parser:
//!
//! | target | test file | what |
//! |---|---|---|
//! | `protocol` | `tests/protocol.rs` | `pendulab_rig::protocol::{SensorFrame, CommandFrame}::decode`, `SequenceGate` |
//! | `config` | `tests/config.rs` | `pendulab_rig::config::load` (controller TOML files) |
//! | `ident_csv` | `tests/ident_csv.rs` | `pendulab_ident::Dataset::from_csv_str` and `Dataset::window` |
//! | `cli` | `crates/cli/tests/fuzz_cli.rs` | the `pendulab` binary on mutated arguments and files |
//!
//! This library holds what they share:
//!
//! - [`Target::run`]: runs a property on a strategy for [`cases`] cases from a fixed seed
//!   (the same inputs on every run, so that CI is deterministic); a failure is shrunk by
//!   proptest, written to the target's corpus directory and reported with its file name.
//! - [`Target::replay`]: runs a property on every file of the target's corpus, so that each
//!   reproducer ever found stays a regression test.
//! - [`Mutation`] and [`mutations`]: byte-level mutations (bit flips, byte writes,
//!   truncation, extension, deletion, duplication, insertion of interesting tokens) of a valid
//!   input, shrinkable to the fewest mutations that still fail.
//!
//! The suite's budget and how to run it longer are in `crates/fuzz/README.md`.

#![warn(missing_docs)]

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

/// The environment variable that overrides every target's number of cases
/// (`PENDULAB_FUZZ_CASES=100000 cargo test -p pendulab-fuzz --release`).
pub const CASES_VAR: &str = "PENDULAB_FUZZ_CASES";

/// The environment variable that changes the seed (any text; hashed into the 32-byte ChaCha
/// seed). Unset: the fixed seed of CI.
pub const SEED_VAR: &str = "PENDULAB_FUZZ_SEED";

/// The number of cases to run: [`CASES_VAR`] if it is set to a positive integer, else
/// `default`.
///
/// # Panics
/// If [`CASES_VAR`] is set but is not a positive integer (a typo must not silently run the
/// default budget).
pub fn cases(default: u32) -> u32 {
    match std::env::var(CASES_VAR) {
        Ok(v) => match v.trim().parse::<u32>() {
            Ok(n) if n > 0 => n,
            _ => panic!("{CASES_VAR}={v:?}: expected a positive integer"),
        },
        Err(_) => default,
    }
}

/// The 32-byte ChaCha seed of a target: a fixed function of the target's name and of
/// [`SEED_VAR`] (empty when unset), by 64-bit FNV-1a spread over four words.
pub fn seed(target: &str) -> [u8; 32] {
    let extra = std::env::var(SEED_VAR).unwrap_or_default();
    let mut out = [0u8; 32];
    for (i, chunk) in out.chunks_mut(8).enumerate() {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in [i as u8, b'/']
            .iter()
            .chain(target.as_bytes())
            .chain(b"/")
            .chain(extra.as_bytes())
        {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        chunk.copy_from_slice(&h.to_le_bytes());
    }
    out
}

/// The directory of a target's corpus, `crates/fuzz/corpus/<target>/`.
pub fn corpus_dir(target: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus")
        .join(target)
}

/// The files of a target's corpus, sorted by name (no corpus directory: none). `README.md`
/// files, which describe the reproducers, are not inputs.
///
/// # Panics
/// If the directory exists but cannot be read.
pub fn corpus_files(target: &str) -> Vec<PathBuf> {
    let dir = corpus_dir(target);
    let Ok(rd) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = rd
        .map(|e| e.expect("reading the corpus directory").path())
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != "README.md"))
        .collect();
    files.sort();
    files
}

/// A fuzz target: a name (its corpus directory) and the file extension of its inputs.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    /// The corpus directory's name under `crates/fuzz/corpus/`.
    pub name: &'static str,
    /// The extension reproducers are written with (`"bin"`, `"toml"`, `"csv"`).
    pub extension: &'static str,
}

impl Target {
    /// Runs `property` on `cases` inputs of `strategy` drawn from [`seed`]`(name)`. The
    /// property returns `Err(message)` for a violated invariant; a panic inside it counts as a
    /// failure too. On failure proptest shrinks the input; the shrunk input, turned into the
    /// bytes of a file by `to_file`, is written to the corpus as `<hash>.<extension>` and the
    /// call panics with its path, the reason and the input.
    ///
    /// # Panics
    /// On a failing case, as described.
    pub fn run<S>(
        &self,
        cases: u32,
        strategy: S,
        to_file: impl Fn(&S::Value) -> Vec<u8>,
        property: impl Fn(&S::Value) -> Result<(), String>,
    ) where
        S: Strategy,
        S::Value: std::fmt::Debug,
    {
        let config = Config {
            cases,
            failure_persistence: None,
            rng_algorithm: RngAlgorithm::ChaCha,
            ..Config::default()
        };
        let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed(self.name));
        let mut runner = TestRunner::new_with_rng(config, rng);
        let result = runner.run(&strategy, |v| property(&v).map_err(TestCaseError::fail));
        match result {
            Ok(()) => {}
            Err(TestError::Abort(r)) => panic!("{}: aborted: {r}", self.name),
            Err(TestError::Fail(reason, input)) => {
                let bytes = to_file(&input);
                let path = self.save(&bytes);
                panic!(
                    "{}: {reason}\nshrunk input saved as {} (commit it: it is replayed on every run)\ninput: {input:?}",
                    self.name,
                    path.display()
                );
            }
        }
    }

    /// Writes a reproducer into the corpus, named by the FNV-1a hash of its bytes; its path.
    ///
    /// # Panics
    /// If the corpus directory cannot be written.
    pub fn save(&self, bytes: &[u8]) -> PathBuf {
        let dir = corpus_dir(self.name);
        std::fs::create_dir_all(&dir).expect("creating the corpus directory");
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in bytes {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        let path = dir.join(format!("{h:016x}.{}", self.extension));
        std::fs::write(&path, bytes).expect("writing the reproducer");
        path
    }

    /// Runs `property` on every corpus file of this target whose name does not start with one
    /// of `skip` (reproducers of bugs not yet fixed, replayed by an ignored test instead); the
    /// number of files replayed.
    ///
    /// # Panics
    /// Naming every corpus file whose replay fails or panics.
    pub fn replay(&self, skip: &[&str], property: impl Fn(&[u8]) -> Result<(), String>) -> usize {
        let mut failures = Vec::new();
        let mut n = 0;
        for path in corpus_files(self.name) {
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            if skip.iter().any(|s| name.starts_with(s)) {
                continue;
            }
            n += 1;
            let bytes = std::fs::read(&path).expect("reading a corpus file");
            match catch_unwind(AssertUnwindSafe(|| property(&bytes))) {
                Ok(Ok(())) => {}
                Ok(Err(e)) => failures.push(format!("{name}: {e}")),
                Err(_) => failures.push(format!("{name}: panicked")),
            }
        }
        assert!(
            failures.is_empty(),
            "{} corpus replays failed:\n{}",
            self.name,
            failures.join("\n")
        );
        n
    }

    /// Runs `property` on the named corpus files only (the reproducers of one known bug).
    ///
    /// # Panics
    /// If a named file is missing, or its replay fails or panics.
    pub fn replay_only(&self, names: &[&str], property: impl Fn(&[u8]) -> Result<(), String>) {
        for name in names {
            let path = corpus_dir(self.name).join(name);
            let bytes = std::fs::read(&path)
                .unwrap_or_else(|e| panic!("{}: cannot read {name}: {e}", self.name));
            match catch_unwind(AssertUnwindSafe(|| property(&bytes))) {
                Ok(Ok(())) => {}
                Ok(Err(e)) => panic!("{}/{name}: {e}", self.name),
                Err(_) => panic!("{}/{name}: panicked", self.name),
            }
        }
    }
}

/// One byte-level change of an input. Positions are taken modulo the input's length at the
/// time the mutation is applied, so every mutation applies to every input (an empty input
/// only grows).
#[derive(Debug, Clone)]
pub enum Mutation {
    /// Flips bit `bit % 8` of byte `at`.
    FlipBit {
        /// Byte position.
        at: usize,
        /// Bit number.
        bit: u8,
    },
    /// Overwrites byte `at` with `value`.
    SetByte {
        /// Byte position.
        at: usize,
        /// New value.
        value: u8,
    },
    /// Keeps the first `len % (length + 1)` bytes.
    Truncate {
        /// New length (modulo).
        len: usize,
    },
    /// Appends bytes.
    Extend {
        /// Appended bytes.
        bytes: Vec<u8>,
    },
    /// Removes `len` bytes from `at` (clamped to the input).
    Delete {
        /// First byte removed.
        at: usize,
        /// Bytes removed.
        len: usize,
    },
    /// Copies `len` bytes from `from` to `to` (inserting them).
    Duplicate {
        /// Start of the copied range.
        from: usize,
        /// Length of the copied range (clamped).
        len: usize,
        /// Insertion point.
        to: usize,
    },
    /// Inserts `token` at `at`.
    Insert {
        /// Insertion point.
        at: usize,
        /// Inserted bytes.
        token: Vec<u8>,
    },
}

impl Mutation {
    /// Applies the mutation to `input`.
    pub fn apply(&self, input: &mut Vec<u8>) {
        let n = input.len();
        match self {
            Mutation::FlipBit { at, bit } if n > 0 => input[at % n] ^= 1 << (bit % 8),
            Mutation::SetByte { at, value } if n > 0 => input[at % n] = *value,
            Mutation::Truncate { len } => input.truncate(len % (n + 1)),
            Mutation::Extend { bytes } => input.extend_from_slice(bytes),
            Mutation::Delete { at, len } if n > 0 => {
                let a = at % n;
                let b = (a + len).min(n);
                input.drain(a..b);
            }
            Mutation::Duplicate { from, len, to } if n > 0 => {
                let a = from % n;
                let b = (a + len).min(n);
                let chunk = input[a..b].to_vec();
                let t = to % (n + 1);
                input.splice(t..t, chunk);
            }
            Mutation::Insert { at, token } => {
                let t = at % (n + 1);
                input.splice(t..t, token.iter().copied());
            }
            _ => {}
        }
    }
}

/// A strategy of single mutations; `tokens` are the interesting byte strings of the format
/// ([`TEXT_TOKENS`] for text formats), inserted whole.
pub fn mutation(tokens: &'static [&'static str]) -> impl Strategy<Value = Mutation> {
    let token = proptest::sample::select(tokens).prop_map(|t| t.as_bytes().to_vec());
    prop_oneof![
        3 => (any::<usize>(), any::<u8>()).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        2 => (any::<usize>(), any::<u8>()).prop_map(|(at, value)| Mutation::SetByte { at, value }),
        1 => any::<usize>().prop_map(|len| Mutation::Truncate { len }),
        1 => proptest::collection::vec(any::<u8>(), 1..16).prop_map(|bytes| Mutation::Extend { bytes }),
        1 => (any::<usize>(), 1usize..32).prop_map(|(at, len)| Mutation::Delete { at, len }),
        1 => (any::<usize>(), 1usize..64, any::<usize>())
            .prop_map(|(from, len, to)| Mutation::Duplicate { from, len, to }),
        3 => (any::<usize>(), token).prop_map(|(at, token)| Mutation::Insert { at, token }),
    ]
}

/// Between `min` and `max` mutations in a row (shrinks towards fewer).
pub fn mutations(
    tokens: &'static [&'static str],
    min: usize,
    max: usize,
) -> impl Strategy<Value = Vec<Mutation>> {
    proptest::collection::vec(mutation(tokens), min..=max)
}

/// Applies `mutations` in order to a copy of `input`.
pub fn mutate(input: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut v = input.to_vec();
    for m in mutations {
        m.apply(&mut v);
    }
    v
}

/// Tokens that break text parsers: numbers at and beyond the edges of `f64` and the integer
/// types, non-finite spellings, signs, separators, quotes, brackets, line ends, a UTF-8 BOM,
/// non-ASCII and invalid UTF-8.
pub const TEXT_TOKENS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "+inf",
    "infinity",
    "1e308",
    "1e309",
    "-1e309",
    "1e-320",
    "4.9e-324",
    "-0",
    "0",
    "-1",
    "1e9",
    "1e300",
    "-1e300",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "9223372036854775807",
    "-9223372036854775808",
    "2147483648",
    "0x10",
    "1_000",
    ".",
    "e",
    "-",
    ",",
    ";",
    "\t",
    " ",
    "\n",
    "\r\n",
    "\"",
    "'",
    "=",
    "[",
    "]",
    "{",
    "}",
    "#",
    "\u{feff}",
    "µ",
    "\u{0}",
    "\u{7f}",
    "θ",
    "𝜃",
    "\u{202e}",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mutations_apply_as_documented() {
        let mut v = b"abcdef".to_vec();
        Mutation::FlipBit { at: 7, bit: 9 }.apply(&mut v); // byte 1, bit 1: 'b' ^ 2 = '`'
        assert_eq!(v, b"a`cdef");
        Mutation::Truncate { len: 10 }.apply(&mut v); // 10 % 7 = 3
        assert_eq!(v, b"a`c");
        Mutation::Duplicate {
            from: 0,
            len: 2,
            to: 3,
        }
        .apply(&mut v);
        assert_eq!(v, b"a`ca`");
        Mutation::Delete { at: 1, len: 100 }.apply(&mut v);
        assert_eq!(v, b"a");
        Mutation::Insert {
            at: 0,
            token: b"xy".to_vec(),
        }
        .apply(&mut v);
        assert_eq!(v, b"xya");
        let mut empty = Vec::new();
        Mutation::FlipBit { at: 0, bit: 0 }.apply(&mut empty);
        Mutation::Delete { at: 0, len: 1 }.apply(&mut empty);
        assert!(empty.is_empty());
    }

    #[test]
    fn the_seed_depends_on_the_target() {
        assert_ne!(seed("protocol"), seed("config"));
        assert_eq!(seed("protocol"), seed("protocol"));
    }
}
