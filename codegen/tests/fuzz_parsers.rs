//! The interface parsers' fuzz targets' entry points (`fuzz/fuzz_targets/codegen_idl.rs`,
//! `codegen_msg.rs`), briefly: on their committed seeds (`fuzz/seeds/<target>/`, valid files)
//! and regressions (`fuzz/regressions/<target>/`), then on a fixed number of inputs mutated from
//! those (proptest: grammar fragments inserted, spans removed, duplicated or truncated,
//! characters replaced) and of random text. They must never panic, and an error must point
//! inside the text. `scripts/fuzz` runs the long campaigns.

use std::path::Path;

use horus_ros_test_support::fuzz::{regressions, seeds};

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestError, TestRunner};

/// Mutated or random inputs (a few seconds in a debug build).
const CASES: u32 = 20_000;

/// Pieces of `.msg`/`.srv`/`.action` files that make mutations reach deep into the parser.
const MSG_FRAGMENTS: &[&str] = &[
    "bool",
    "byte",
    "char",
    "int8",
    "uint8",
    "int64",
    "float32",
    "float64",
    "string",
    "wstring",
    "string<=",
    "wstring<=",
    "time",
    "duration",
    "std_msgs/Header",
    "Header",
    "pkg/Name",
    "[",
    "]",
    "[<=",
    "[]",
    "[3]",
    "<=",
    " ",
    "  ",
    "\t",
    "\n",
    "#",
    "# [m/s]",
    "=",
    "---",
    "\n---\n",
    "'",
    "\"",
    "\\'",
    "\\\"",
    ",",
    "true",
    "False",
    "1",
    "0x1F",
    "-1",
    "1_000",
    "1.5e3",
    "nan",
    "-inf",
    "[1, 2, 3]",
    "['a', \"b\"]",
    "CONST",
    "A_B",
    "_",
    "__",
    "é",
    "\u{2028}",
    "99999999999999999999999999999999999999999",
    "\r\n",
];

/// Pieces of IDL that make mutations reach deep into the parser.
const IDL_FRAGMENTS: &[&str] = &[
    "module",
    "struct",
    "typedef",
    "const",
    "enum",
    "sequence<",
    "string<",
    "wstring<",
    ">",
    "<",
    "{",
    "}",
    ";",
    "::",
    ":",
    ",",
    "[",
    "]",
    "(",
    ")",
    "=",
    "@",
    "-",
    "\"",
    "L\"",
    "\\",
    "'",
    "#include",
    "/*",
    "*/",
    "//",
    "\n",
    " ",
    "0",
    "1",
    "-1",
    "0x1F",
    "017",
    "1.5e3",
    ".5",
    "1d",
    "TRUE",
    "FALSE",
    "@default (value=",
    "@verbatim (language=\"comment\", text=",
    "@unit (value=",
    "\"(1, 2)\"",
    "\"()\"",
    "\"('a',)\"",
    "\"(\"",
    "uint8",
    "long",
    "unsigned",
    "long double",
    "double",
    "boolean",
    "octet",
    "char",
    "wchar",
    "x_Constants",
    "_Request",
    "_Response",
    "_Goal",
    "_Result",
    "_Feedback",
    "structure_needs_at_least_one_member",
    "pkg::msg::T",
    "\\x4",
    "\\u12",
    "\\777",
    "é",
    "\u{2028}",
    "99999999999999999999999999999999999999999",
];

/// One change to an input; positions are taken modulo the input's length.
#[derive(Clone, Debug)]
enum Mutation {
    Insert { at: usize, fragment: usize },
    Remove { at: usize, len: usize },
    Duplicate { from: usize, at: usize, len: usize },
    SetByte { at: usize, byte: u8 },
    Truncate { at: usize },
}

fn mutation(fragments: usize) -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0..fragments)
            .prop_map(|(at, fragment)| Mutation::Insert { at, fragment }),
        3 => (any::<usize>(), 1..24usize).prop_map(|(at, len)| Mutation::Remove { at, len }),
        2 => (any::<usize>(), any::<usize>(), 1..64usize)
            .prop_map(|(from, at, len)| Mutation::Duplicate { from, at, len }),
        1 => (any::<usize>(), any::<u8>()).prop_map(|(at, byte)| Mutation::SetByte { at, byte }),
        1 => any::<usize>().prop_map(|at| Mutation::Truncate { at }),
    ]
}

fn apply(fragments: &[&str], input: &mut Vec<u8>, m: &Mutation) {
    let pos = |at: usize, len: usize| if len == 0 { 0 } else { at % len };
    match m {
        Mutation::Insert { at, fragment } => {
            let i = pos(*at, input.len() + 1);
            input.splice(i..i, fragments[*fragment].bytes());
        }
        Mutation::Remove { at, len } => {
            if !input.is_empty() {
                let i = pos(*at, input.len());
                input.drain(i..(i + len).min(input.len()));
            }
        }
        Mutation::Duplicate { from, at, len } => {
            if !input.is_empty() {
                let from = pos(*from, input.len());
                let chunk = input[from..(from + len).min(input.len())].to_vec();
                let at = pos(*at, input.len() + 1);
                input.splice(at..at, chunk);
            }
        }
        Mutation::SetByte { at, byte } => {
            if !input.is_empty() {
                let i = pos(*at, input.len());
                input[i] = *byte;
            }
        }
        Mutation::Truncate { at } => input.truncate(pos(*at, input.len() + 1)),
    }
}

/// An input: a mutated seed, or random fragments and bytes.
#[derive(Clone, Debug)]
enum Case {
    Mutated {
        seed: usize,
        mutations: Vec<Mutation>,
    },
    Random {
        fragments: Vec<usize>,
        bytes: Vec<u8>,
    },
}

fn build(fragments: &[&str], inputs: &[(String, Vec<u8>)], case: &Case) -> Vec<u8> {
    match case {
        Case::Mutated { seed, mutations } => {
            let mut input = inputs[*seed].1.clone();
            for m in mutations {
                apply(fragments, &mut input, m);
            }
            input
        }
        Case::Random {
            fragments: picked,
            bytes,
        } => {
            let mut input: Vec<u8> = picked.iter().flat_map(|f| fragments[*f].bytes()).collect();
            input.extend_from_slice(bytes);
            input
        }
    }
}

/// Runs `entry` on the seeds (each of which `valid` must accept), the regressions and mutants.
fn campaign(
    target: &str,
    fragments: &[&str],
    valid: fn(&str, &[u8]) -> Result<(), String>,
    entry: fn(&[u8]),
) {
    let seeds = seeds(target);
    assert!(!seeds.is_empty(), "{target} has no seeds in fuzz/seeds/");
    for (name, bytes) in &seeds {
        valid(name, bytes).unwrap_or_else(|e| panic!("seed {name} does not parse: {e}"));
    }
    let regressions = regressions(target);
    let inputs: Vec<(String, Vec<u8>)> = seeds.into_iter().chain(regressions).collect();
    for (_, bytes) in &inputs {
        entry(bytes);
    }
    let n = inputs.len();
    let case = prop_oneof![
        9 => (0..n, vec(mutation(fragments.len()), 1..8))
            .prop_map(|(seed, mutations)| Case::Mutated { seed, mutations }),
        1 => (vec(0..fragments.len(), 0..48), vec(any::<u8>(), 0..32))
            .prop_map(|(fragments, bytes)| Case::Random { fragments, bytes }),
    ];
    let mut runner = TestRunner::new(Config {
        cases: CASES,
        failure_persistence: None,
        ..Config::default()
    });
    let result = runner.run(&case, |case| {
        entry(&build(fragments, &inputs, &case));
        Ok(())
    });
    match result {
        Ok(()) => {}
        Err(TestError::Fail(why, case)) => panic!(
            "{target} failed ({why}) on {:?} (from {case:?})",
            String::from_utf8_lossy(&build(fragments, &inputs, &case))
        ),
        Err(e) => panic!("{target}: {e}"),
    }
}

#[test]
fn codegen_idl() {
    campaign(
        "codegen_idl",
        IDL_FRAGMENTS,
        |name, bytes| {
            let text = std::str::from_utf8(bytes).map_err(|e| e.to_string())?;
            horus_ros_codegen::idl::parse_idl(Path::new(name), text)
                .map(|_| ())
                .map_err(|e| e.to_string())
        },
        horus_ros_codegen::fuzzing::idl,
    );
}

#[test]
fn codegen_msg() {
    campaign(
        "codegen_msg",
        MSG_FRAGMENTS,
        |_, bytes| horus_ros_codegen::fuzzing::parse_msg(bytes).map(|_| ()),
        horus_ros_codegen::fuzzing::msg,
    );
}
