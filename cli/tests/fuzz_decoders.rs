//! The fuzz targets' entry points (`fuzz/fuzz_targets/`), briefly: each on its committed seeds
//! (`fuzz/seeds/<target>/`, valid encodings) and on every input that once crashed it
//! (`fuzz/regressions/<target>/`), then on a fixed number of inputs mutated from those (proptest:
//! bit flips, byte and length overwrites, insertions, deletions, truncations, splices) and of
//! random bytes. `scripts/fuzz` runs the long campaigns (cargo-fuzz, nightly). No DDS: pure
//! decoding.

#[path = "fuzz_decoders/seeds.rs"]
mod seeds;

use std::collections::BTreeMap;

use horus_ros_test_support::fuzz::{files, fuzz_dir};

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestError, TestRunner};

/// Mutated or random inputs per target (each target's whole run takes a few seconds at most in a
/// debug build).
const CASES: u32 = 3000;

/// Set to write `fuzz/seeds/` from [`seeds::seeds`] instead of checking it.
const WRITE_SEEDS_ENV: &str = "HORUS_ROS_WRITE_FUZZ_SEEDS";

/// A fuzz target's entry point.
type Entry = fn(&[u8]);

/// Every fuzz target and its entry point, as `fuzz/fuzz_targets/<name>.rs` calls it.
const TARGETS: &[(&str, Entry)] = &[
    (
        "cdr_participant_entities_info",
        horus_ros_msgs::fuzzing::participant_entities_info,
    ),
    (
        "cdr_service_payload",
        horus_ros_msgs::fuzzing::service_payload,
    ),
    (
        "cdr_type_description",
        horus_ros_msgs::fuzzing::type_description,
    ),
    ("user_data", horus_ros_msgs::fuzzing::user_data),
    ("rmw_user_data", horus_ros_rmw::fuzzing::user_data),
    ("dds_names", horus_ros_rmw::fuzzing::dds_names),
    ("service_wire_cyclone", horus_ros_services::fuzzing::cyclone),
    (
        "service_wire_fastrtps",
        horus_ros_services::fuzzing::fastrtps,
    ),
    ("dynamic_cdr", horus_ros_dynamic::fuzzing::cdr),
    ("dynamic_yaml", horus_ros_dynamic::fuzzing::yaml),
    (
        "dynamic_description",
        horus_ros_dynamic::fuzzing::description,
    ),
];

fn entry(target: &str) -> Entry {
    TARGETS
        .iter()
        .find(|(name, _)| *name == target)
        .map(|(_, f)| *f)
        .unwrap_or_else(|| panic!("no fuzz target {target}"))
}

/// One change to an input; positions are taken modulo the input's length.
#[derive(Clone, Debug)]
enum Mutation {
    FlipBit {
        at: usize,
        bit: u8,
    },
    SetByte {
        at: usize,
        byte: u8,
    },
    /// A 32-bit little- or big-endian word: lengths and counts are where decoders go wrong.
    SetWord {
        at: usize,
        word: u32,
        big_endian: bool,
    },
    Insert {
        at: usize,
        bytes: Vec<u8>,
    },
    Remove {
        at: usize,
        len: usize,
    },
    Truncate {
        at: usize,
    },
    /// Copies `len` bytes from `from` over `at` (structure repeated elsewhere).
    Splice {
        from: usize,
        at: usize,
        len: usize,
    },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let word = prop_oneof![
        Just(0u32),
        Just(1),
        Just(0x7fff_ffff),
        Just(0x8000_0000),
        Just(u32::MAX),
        0..300u32,
        any::<u32>(),
    ];
    prop_oneof![
        (any::<usize>(), 0..8u8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        (any::<usize>(), any::<u8>()).prop_map(|(at, byte)| Mutation::SetByte { at, byte }),
        (any::<usize>(), word, any::<bool>()).prop_map(|(at, word, big_endian)| {
            Mutation::SetWord {
                at,
                word,
                big_endian,
            }
        }),
        (any::<usize>(), vec(any::<u8>(), 1..16))
            .prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        (any::<usize>(), 1..16usize).prop_map(|(at, len)| Mutation::Remove { at, len }),
        any::<usize>().prop_map(|at| Mutation::Truncate { at }),
        (any::<usize>(), any::<usize>(), 1..32usize).prop_map(|(from, at, len)| Mutation::Splice {
            from,
            at,
            len
        }),
    ]
}

fn apply(input: &mut Vec<u8>, m: &Mutation) {
    let pos = |at: usize, len: usize| if len == 0 { 0 } else { at % len };
    match m {
        Mutation::FlipBit { at, bit } => {
            if !input.is_empty() {
                let i = pos(*at, input.len());
                input[i] ^= 1 << bit;
            }
        }
        Mutation::SetByte { at, byte } => {
            if !input.is_empty() {
                let i = pos(*at, input.len());
                input[i] = *byte;
            }
        }
        Mutation::SetWord {
            at,
            word,
            big_endian,
        } => {
            let bytes = if *big_endian {
                word.to_be_bytes()
            } else {
                word.to_le_bytes()
            };
            let i = pos(*at, input.len() + 1);
            for (k, b) in bytes.iter().enumerate() {
                match input.get_mut(i + k) {
                    Some(slot) => *slot = *b,
                    None => input.push(*b),
                }
            }
        }
        Mutation::Insert { at, bytes } => {
            let i = pos(*at, input.len() + 1);
            input.splice(i..i, bytes.iter().copied());
        }
        Mutation::Remove { at, len } => {
            if !input.is_empty() {
                let i = pos(*at, input.len());
                let end = (i + len).min(input.len());
                input.drain(i..end);
            }
        }
        Mutation::Truncate { at } => {
            let i = pos(*at, input.len() + 1);
            input.truncate(i);
        }
        Mutation::Splice { from, at, len } => {
            if !input.is_empty() {
                let from = pos(*from, input.len());
                let chunk: Vec<u8> = input[from..(from + len).min(input.len())].to_vec();
                let at = pos(*at, input.len());
                for (k, b) in chunk.into_iter().enumerate() {
                    if let Some(slot) = input.get_mut(at + k) {
                        *slot = b;
                    }
                }
            }
        }
    }
}

/// An input to try: a mutated seed, or random bytes after a seed's first two (selector) bytes.
#[derive(Clone, Debug)]
enum Case {
    Mutated {
        seed: usize,
        mutations: Vec<Mutation>,
    },
    Random {
        seed: usize,
        bytes: Vec<u8>,
    },
}

fn build(inputs: &[(String, Vec<u8>)], case: &Case) -> Vec<u8> {
    match case {
        Case::Mutated { seed, mutations } => {
            let mut input = inputs[*seed].1.clone();
            for m in mutations {
                apply(&mut input, m);
            }
            input
        }
        Case::Random { seed, bytes } => {
            let mut input: Vec<u8> = inputs[*seed].1.iter().take(2).copied().collect();
            input.extend_from_slice(bytes);
            input
        }
    }
}

/// Runs `target` on its seeds and regression inputs, then on [`CASES`] mutated or random ones.
fn fuzz(target: &str) {
    let run = entry(target);
    let dir = fuzz_dir();
    let seeds = files(&dir.join("seeds").join(target));
    assert!(!seeds.is_empty(), "{target} has no seeds in fuzz/seeds/");
    let regressions = files(&dir.join("regressions").join(target));
    let inputs: Vec<(String, Vec<u8>)> = seeds.into_iter().chain(regressions).collect();
    for (name, bytes) in &inputs {
        eprintln!("{target}: {name}");
        run(bytes);
    }
    let n = inputs.len();
    let case = prop_oneof![
        9 => (0..n, vec(mutation(), 1..8))
            .prop_map(|(seed, mutations)| Case::Mutated { seed, mutations }),
        1 => (0..n, vec(any::<u8>(), 0..128)).prop_map(|(seed, bytes)| Case::Random { seed, bytes }),
    ];
    let mut runner = TestRunner::new(Config {
        cases: CASES,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&case, |case| {
        run(&build(&inputs, &case));
        Ok(())
    });
    match result {
        Ok(()) => {}
        Err(TestError::Fail(why, case)) => panic!(
            "{target} failed ({why}) on {:02x?} (from {case:?})",
            build(&inputs, &case)
        ),
        Err(e) => panic!("{target}: {e}"),
    }
}

#[test]
fn committed_seeds_are_the_generated_ones() {
    let write = std::env::var_os(WRITE_SEEDS_ENV).is_some();
    let seeds_dir = fuzz_dir().join("seeds");
    for (target, _) in TARGETS {
        let dir = seeds_dir.join(target);
        let generated: BTreeMap<String, Vec<u8>> = seeds::seeds(target).into_iter().collect();
        if write {
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).expect("fuzz/seeds/<target> can be created");
            for (name, bytes) in &generated {
                std::fs::write(dir.join(name), bytes).expect("a seed can be written");
            }
        }
        assert_eq!(
            files(&dir),
            generated,
            "fuzz/seeds/{target} differs from what tests/fuzz_decoders/seeds.rs builds (write \
             them with {WRITE_SEEDS_ENV}=1)"
        );
    }
}

#[test]
fn every_target_is_built_by_cargo_fuzz() {
    let manifest =
        std::fs::read_to_string(fuzz_dir().join("Cargo.toml")).expect("fuzz/Cargo.toml exists");
    for (target, _) in TARGETS {
        assert!(
            manifest.contains(&format!("name = \"{target}\"")),
            "fuzz/Cargo.toml lacks a [[bin]] for {target}"
        );
        let source = fuzz_dir().join("fuzz_targets").join(format!("{target}.rs"));
        let text = std::fs::read_to_string(&source).expect("the fuzz target's source exists");
        assert!(text.contains("fuzz_target!"), "{}", source.display());
    }
}

#[test]
fn cdr_participant_entities_info() {
    fuzz("cdr_participant_entities_info");
}

#[test]
fn cdr_service_payload() {
    fuzz("cdr_service_payload");
}

#[test]
fn cdr_type_description() {
    fuzz("cdr_type_description");
}

#[test]
fn user_data() {
    fuzz("user_data");
}

#[test]
fn rmw_user_data() {
    fuzz("rmw_user_data");
}

#[test]
fn dds_names() {
    fuzz("dds_names");
}

#[test]
fn service_wire_cyclone() {
    fuzz("service_wire_cyclone");
}

#[test]
fn service_wire_fastrtps() {
    fuzz("service_wire_fastrtps");
}

#[test]
fn dynamic_cdr() {
    fuzz("dynamic_cdr");
}

#[test]
fn dynamic_yaml() {
    fuzz("dynamic_yaml");
}

#[test]
fn dynamic_description() {
    fuzz("dynamic_description");
}
