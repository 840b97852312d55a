//! `horus_ros_msgs::runtime` and `WString` as generated structs use them: hand-written `Serialize`
//! through `Bounded`, derived `Deserialize` with the array helper.
//!
//! Mirrors of test_msgs `Arrays`, `BoundedSequences`, `Strings` and `WStrings` (same fields, same
//! order) are checked against the CDR that Jazzy's rclpy writes for the same values
//! (`serialize_message`, rmw_fastrtps_cpp; no ROS graph needed): tests/runtime/test_msgs_bytes.py
//! builds them. The interpreter is `HORUS_ROS_INTEROP_PYTHON`, else the workspace's
//! `target/interop-venv` (`scripts/setup`); without it these tests fail.

use std::collections::HashMap;
use std::error::Error as _;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::OnceLock;

use horus_ros_msgs::cdr::{from_cdr, to_cdr, to_cdr_body, CdrError};
use horus_ros_msgs::runtime::{default_array, take_bound_error, BoundError, BoundKind, Bounded};
use horus_ros_msgs::{Byte, DescriptionBuilder, Message, TypeDescription, WString};
use serde::ser::{SerializeStruct, Serializer};
use serde::{Deserialize, Serialize};

/// A struct as the generator emits it: derived `Deserialize`, `Serialize` through [`Bounded`]
/// (`$field: $ty => string_bound, sequence_bound`), and a [`Message`] impl.
macro_rules! mirror {
    (
        $name:ident = $ros:literal {
            $(
                $(#[$fmeta:meta])*
                $field:ident : $ty:ty $(=> $sb:expr, $qb:expr)?
            ),* $(,)?
        }
    ) => {
        #[derive(Clone, Debug, PartialEq, Deserialize)]
        struct $name {
            $( $(#[$fmeta])* $field: $ty, )*
        }

        impl Serialize for $name {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                let fields = [$(stringify!($field)),*].len();
                let mut s = serializer.serialize_struct(stringify!($name), fields)?;
                $(
                    s.serialize_field(
                        stringify!($field),
                        &Bounded::new(
                            &self.$field,
                            stringify!($field),
                            mirror!(@bound $($sb)?),
                            mirror!(@bound $($qb)?),
                        ),
                    )?;
                )*
                s.end()
            }
        }

        impl Message for $name {
            const TYPE_NAME: &'static str = $ros;
            fn type_description() -> TypeDescription {
                let b = DescriptionBuilder::new($ros);
                $( let b = b.field::<$ty>(stringify!($field)); )*
                b.build()
            }
        }
    };
    (@bound) => { None };
    (@bound $b:expr) => { $b };
}

mirror! {
    BasicTypes = "test_msgs/msg/BasicTypes" {
        bool_value: bool,
        byte_value: Byte,
        char_value: u8,
        float32_value: f32,
        float64_value: f64,
        int8_value: i8,
        uint8_value: u8,
        int16_value: i16,
        uint16_value: u16,
        int32_value: i32,
        uint32_value: u32,
        int64_value: i64,
        uint64_value: u64,
    }
}

mirror! {
    Defaults = "test_msgs/msg/Defaults" {
        bool_value: bool,
        byte_value: Byte,
        char_value: u8,
        float32_value: f32,
        float64_value: f64,
        int8_value: i8,
        uint8_value: u8,
        int16_value: i16,
        uint16_value: u16,
        int32_value: i32,
        uint32_value: u32,
        int64_value: i64,
        uint64_value: u64,
    }
}

mirror! {
    Constants = "test_msgs/msg/Constants" {
        structure_needs_at_least_one_member: u8,
    }
}

mirror! {
    Arrays = "test_msgs/msg/Arrays" {
        bool_values: [bool; 3],
        byte_values: [Byte; 3],
        char_values: [u8; 3],
        float32_values: [f32; 3],
        float64_values: [f64; 3],
        int8_values: [i8; 3],
        uint8_values: [u8; 3],
        int16_values: [i16; 3],
        uint16_values: [u16; 3],
        int32_values: [i32; 3],
        uint32_values: [u32; 3],
        int64_values: [i64; 3],
        uint64_values: [u64; 3],
        #[serde(deserialize_with = "::horus_ros_msgs::runtime::array::deserialize")]
        string_values: [String; 3],
        #[serde(with = "::horus_ros_msgs::runtime::array")]
        basic_types_values: [BasicTypes; 3],
        constants_values: [Constants; 3],
        defaults_values: [Defaults; 3],
        bool_values_default: [bool; 3],
        byte_values_default: [Byte; 3],
        char_values_default: [u8; 3],
        float32_values_default: [f32; 3],
        float64_values_default: [f64; 3],
        int8_values_default: [i8; 3],
        uint8_values_default: [u8; 3],
        int16_values_default: [i16; 3],
        uint16_values_default: [u16; 3],
        int32_values_default: [i32; 3],
        uint32_values_default: [u32; 3],
        int64_values_default: [i64; 3],
        uint64_values_default: [u64; 3],
        string_values_default: [String; 3],
        alignment_check: i32,
    }
}

mirror! {
    BoundedSequences = "test_msgs/msg/BoundedSequences" {
        bool_values: Vec<bool> => None, Some(3),
        byte_values: Vec<Byte> => None, Some(3),
        char_values: Vec<u8> => None, Some(3),
        float32_values: Vec<f32> => None, Some(3),
        float64_values: Vec<f64> => None, Some(3),
        int8_values: Vec<i8> => None, Some(3),
        uint8_values: Vec<u8> => None, Some(3),
        int16_values: Vec<i16> => None, Some(3),
        uint16_values: Vec<u16> => None, Some(3),
        int32_values: Vec<i32> => None, Some(3),
        uint32_values: Vec<u32> => None, Some(3),
        int64_values: Vec<i64> => None, Some(3),
        uint64_values: Vec<u64> => None, Some(3),
        string_values: Vec<String> => None, Some(3),
        basic_types_values: Vec<BasicTypes> => None, Some(3),
        constants_values: Vec<Constants> => None, Some(3),
        defaults_values: Vec<Defaults> => None, Some(3),
        bool_values_default: Vec<bool> => None, Some(3),
        byte_values_default: Vec<Byte> => None, Some(3),
        char_values_default: Vec<u8> => None, Some(3),
        float32_values_default: Vec<f32> => None, Some(3),
        float64_values_default: Vec<f64> => None, Some(3),
        int8_values_default: Vec<i8> => None, Some(3),
        uint8_values_default: Vec<u8> => None, Some(3),
        int16_values_default: Vec<i16> => None, Some(3),
        uint16_values_default: Vec<u16> => None, Some(3),
        int32_values_default: Vec<i32> => None, Some(3),
        uint32_values_default: Vec<u32> => None, Some(3),
        int64_values_default: Vec<i64> => None, Some(3),
        uint64_values_default: Vec<u64> => None, Some(3),
        string_values_default: Vec<String> => None, Some(3),
        alignment_check: i32,
    }
}

mirror! {
    Strings = "test_msgs/msg/Strings" {
        string_value: String,
        string_value_default1: String,
        string_value_default2: String,
        string_value_default3: String,
        string_value_default4: String,
        string_value_default5: String,
        bounded_string_value: String => Some(22), None,
        bounded_string_value_default1: String => Some(22), None,
        bounded_string_value_default2: String => Some(22), None,
        bounded_string_value_default3: String => Some(22), None,
        bounded_string_value_default4: String => Some(22), None,
        bounded_string_value_default5: String => Some(22), None,
    }
}

mirror! {
    WStrings = "test_msgs/msg/WStrings" {
        wstring_value: WString,
        wstring_value_default1: WString,
        wstring_value_default2: WString,
        wstring_value_default3: WString,
        array_of_wstrings: [WString; 3],
        bounded_sequence_of_wstrings: Vec<WString> => None, Some(3),
        unbounded_sequence_of_wstrings: Vec<WString>,
    }
}

/// `basic(m, i)` of test_msgs_bytes.py, for `BasicTypes` or `Defaults`.
macro_rules! basic {
    ($t:ident, $i:expr) => {{
        let i: u8 = $i;
        $t {
            bool_value: i % 2 == 0,
            byte_value: Byte(0x10 + i),
            char_value: 0x41 + i,
            float32_value: 1.5 + f32::from(i),
            float64_value: -2.25 * f64::from(i),
            int8_value: -5 - i8::try_from(i).expect("small"),
            uint8_value: 200 + i,
            int16_value: -1000 - i16::from(i),
            uint16_value: 60000 + u16::from(i),
            int32_value: -100_000 - i32::from(i),
            uint32_value: 4_000_000_000 + u32::from(i),
            int64_value: -(1_i64 << 40) - i64::from(i),
            uint64_value: (1_u64 << 63) + u64::from(i),
        }
    }};
}

const CONSTANTS: Constants = Constants {
    structure_needs_at_least_one_member: 0,
};

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| (*s).to_owned()).collect()
}

fn wstrings(v: &[&str]) -> Vec<WString> {
    v.iter().map(|s| WString::from(*s)).collect()
}

fn array<T: std::fmt::Debug, const N: usize>(v: Vec<T>) -> [T; N] {
    v.try_into().expect("length")
}

fn arrays() -> Arrays {
    let string_values: [String; 3] = array(strings(&["", "zwei", "drei und mehr"]));
    Arrays {
        bool_values: [true, false, true],
        byte_values: [Byte(0), Byte(0x7f), Byte(0xff)],
        char_values: [0, 65, 255],
        float32_values: [1.125, -0.5, 65536.0],
        float64_values: [1.2345, 0.0, -1e300],
        int8_values: [i8::MIN, 0, i8::MAX],
        uint8_values: [0, 1, 255],
        int16_values: [i16::MIN, 5, i16::MAX],
        uint16_values: [0, 2, u16::MAX],
        int32_values: [i32::MIN, 7, i32::MAX],
        uint32_values: [0, 9, u32::MAX],
        int64_values: [i64::MIN, 11, i64::MAX],
        uint64_values: [0, 13, u64::MAX],
        string_values: string_values.clone(),
        basic_types_values: [
            basic!(BasicTypes, 0),
            basic!(BasicTypes, 1),
            basic!(BasicTypes, 2),
        ],
        constants_values: [CONSTANTS; 3],
        defaults_values: [
            basic!(Defaults, 10),
            basic!(Defaults, 11),
            basic!(Defaults, 12),
        ],
        bool_values_default: [true, false, true],
        byte_values_default: [Byte(0), Byte(0x7f), Byte(0xff)],
        char_values_default: [0, 65, 255],
        float32_values_default: [1.125, -0.5, 65536.0],
        float64_values_default: [1.2345, 0.0, -1e300],
        int8_values_default: [i8::MIN, 0, i8::MAX],
        uint8_values_default: [0, 1, 255],
        int16_values_default: [i16::MIN, 5, i16::MAX],
        uint16_values_default: [0, 2, u16::MAX],
        int32_values_default: [i32::MIN, 7, i32::MAX],
        uint32_values_default: [0, 9, u32::MAX],
        int64_values_default: [i64::MIN, 11, i64::MAX],
        uint64_values_default: [0, 13, u64::MAX],
        string_values_default: string_values,
        alignment_check: 0x1234_5678,
    }
}

fn bounded_sequences() -> BoundedSequences {
    BoundedSequences {
        bool_values: vec![true],
        byte_values: vec![],
        char_values: vec![1, 2, 3],
        float32_values: vec![2.5, -1.0],
        float64_values: vec![1e-300],
        int8_values: vec![-1, -2],
        uint8_values: vec![250],
        int16_values: vec![],
        uint16_values: vec![65535, 0, 1],
        int32_values: vec![-7],
        uint32_values: vec![8, 9],
        int64_values: vec![-1],
        uint64_values: vec![],
        string_values: strings(&["a", "", "ccc"]),
        basic_types_values: vec![basic!(BasicTypes, 5)],
        constants_values: vec![CONSTANTS; 2],
        defaults_values: vec![],
        bool_values_default: vec![true],
        byte_values_default: vec![],
        char_values_default: vec![1, 2, 3],
        float32_values_default: vec![2.5, -1.0],
        float64_values_default: vec![1e-300],
        int8_values_default: vec![-1, -2],
        uint8_values_default: vec![250],
        int16_values_default: vec![],
        uint16_values_default: vec![65535, 0, 1],
        int32_values_default: vec![-7],
        uint32_values_default: vec![8, 9],
        int64_values_default: vec![-1],
        uint64_values_default: vec![],
        string_values_default: strings(&["a", "", "ccc"]),
        alignment_check: 0x1234_5678,
    }
}

fn strings_msg() -> Strings {
    Strings {
        string_value: "unbounded ünïcode".into(),
        string_value_default1: "Hello world!".into(),
        string_value_default2: "Hello'world!".into(),
        string_value_default3: "Hello\"world!".into(),
        string_value_default4: "Hello'world!".into(),
        string_value_default5: "Hello\"world!".into(),
        // 22 bytes: exactly the bound.
        bounded_string_value: "0123456789abcdefghijkl".into(),
        bounded_string_value_default1: "Hello world!".into(),
        bounded_string_value_default2: "Hello'world!".into(),
        bounded_string_value_default3: "Hello\"world!".into(),
        bounded_string_value_default4: "Hello'world!".into(),
        bounded_string_value_default5: "Hello\"world!".into(),
    }
}

fn wstrings_msg() -> WStrings {
    WStrings {
        wstring_value: "aé😀 wide".into(),
        wstring_value_default1: "Hello world!".into(),
        wstring_value_default2: "Hellö wörld!".into(),
        wstring_value_default3: "ハローワールド".into(),
        array_of_wstrings: array(wstrings(&["x", "", "yz😀"])),
        bounded_sequence_of_wstrings: wstrings(&["q", "ü"]),
        unbounded_sequence_of_wstrings: wstrings(&["ab", "c", "", "d"]),
    }
}

/// The Python interpreter with Jazzy's rclpy.
fn python() -> PathBuf {
    horus_ros_test_support::jazzy::python()
}

/// Runs tests/runtime/test_msgs_bytes.py with `args`, `stdin` as its input; returns its output.
fn run_script(args: &[&str], stdin: &str) -> String {
    use std::io::Write as _;
    let python = python();
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/runtime/test_msgs_bytes.py");
    let mut child = Command::new(&python)
        .arg(&script)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| {
            panic!(
                "cannot run {} ({e}): these tests need Jazzy's rclpy; set HORUS_ROS_INTEROP_PYTHON \
                 or create target/interop-venv with scripts/setup",
                python.display()
            )
        });
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin.as_bytes())
        .expect("write to the script");
    let out = child.wait_with_output().expect("script output");
    assert!(
        out.status.success(),
        "{} {} failed: {}",
        python.display(),
        script.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// rclpy's serialized bytes per test_msgs type name (the script runs once per test binary).
fn rclpy_bytes() -> &'static HashMap<String, Vec<u8>> {
    static BYTES: OnceLock<HashMap<String, Vec<u8>>> = OnceLock::new();
    BYTES.get_or_init(|| {
        run_script(&[], "")
            .lines()
            .filter_map(|line| line.split_once(' '))
            .map(|(name, hex)| (name.to_owned(), unhex(hex)))
            .collect()
    })
}

fn unhex(hex: &str) -> Vec<u8> {
    (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).expect("hex"))
        .collect()
}

fn rclpy(name: &str) -> &'static [u8] {
    rclpy_bytes()
        .get(name)
        .unwrap_or_else(|| panic!("test_msgs_bytes.py printed no {name}"))
}

/// Checks our encoding against rclpy's.
///
/// rclpy's buffer is as long as rmw_fastrtps's size estimate (`rmw_serialize` sets
/// `buffer_length` to `get_serialized_size`), which can exceed what it writes: one more 4-byte
/// unit per wstring (`wchar_size * (size + 1)`) and alignment before an empty sequence
/// (`alignment(current_alignment, item_size)` with no item); rosidl_typesupport_fastrtps_c
/// `msg__type_support_c.cpp.em`. The tail is unwritten buffer. Of the bytes it wrote, alignment
/// gaps are unwritten too (Fast CDR's `Cdr::align` only moves the position) while we write
/// zeros. So a byte may differ only where ours is 0, and differing bytes come in runs shorter
/// than 8 (the largest gap is 7 bytes, before a `double`). [`rclpy_decodes_our_bytes`] and
/// [`rclpy_bytes_decode_to_equal_values`] check the values both ways.
fn assert_same_cdr(name: &str, ours: &[u8], theirs: &[u8]) {
    assert!(
        theirs.len() >= ours.len(),
        "{name}: rclpy wrote {} bytes, we {}",
        theirs.len(),
        ours.len()
    );
    let theirs = &theirs[..ours.len()];
    let mut run = 0;
    for (i, (a, b)) in ours.iter().zip(theirs).enumerate() {
        if a == b {
            run = 0;
            continue;
        }
        run += 1;
        assert!(
            *a == 0 && run < 8,
            "{name}: byte {i} is {a:#04x}, rclpy wrote {b:#04x}\nours:  {ours:02x?}\nrclpy: {theirs:02x?}"
        );
    }
}

#[test]
fn arrays_bytes_equal_rclpy() {
    let ours = to_cdr(&arrays()).expect("encode");
    assert_same_cdr("Arrays", &ours, rclpy("Arrays"));
}

#[test]
fn bounded_sequences_bytes_equal_rclpy() {
    let ours = to_cdr(&bounded_sequences()).expect("encode");
    assert_same_cdr("BoundedSequences", &ours, rclpy("BoundedSequences"));
}

#[test]
fn strings_bytes_equal_rclpy() {
    let ours = to_cdr(&strings_msg()).expect("encode");
    assert_same_cdr("Strings", &ours, rclpy("Strings"));
}

#[test]
fn wstrings_bytes_equal_rclpy() {
    let ours = to_cdr(&wstrings_msg()).expect("encode");
    assert_same_cdr("WStrings", &ours, rclpy("WStrings"));
    // wstring_value "aé😀 wide": a count of 9 UTF-16 units, then each unit as a 4-byte uint32.
    let expected: Vec<u8> = [
        9_u32, 0x61, 0xe9, 0xd83d, 0xde00, 0x20, 0x77, 0x69, 0x64, 0x65,
    ]
    .iter()
    .flat_map(|u| u.to_le_bytes())
    .collect();
    assert_eq!(ours[4..4 + expected.len()], expected[..]);
}

/// rclpy decodes our bytes (without alignment-gap noise) to the values it built itself.
#[test]
fn rclpy_decodes_our_bytes() {
    let mut input = String::new();
    for (name, bytes) in [
        ("Arrays", to_cdr(&arrays())),
        ("BoundedSequences", to_cdr(&bounded_sequences())),
        ("Strings", to_cdr(&strings_msg())),
        ("WStrings", to_cdr(&wstrings_msg())),
    ] {
        let hex: String = bytes
            .expect("encode")
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        input.push_str(&format!("{name} {hex}\n"));
    }
    let out = run_script(&["check"], &input);
    assert_eq!(
        out,
        "Arrays ok\nBoundedSequences ok\nStrings ok\nWStrings ok\n"
    );
}

#[test]
fn rclpy_bytes_decode_to_equal_values() {
    assert_eq!(
        from_cdr::<Arrays>(rclpy("Arrays")).expect("Arrays"),
        arrays()
    );
    assert_eq!(
        from_cdr::<BoundedSequences>(rclpy("BoundedSequences")).expect("BoundedSequences"),
        bounded_sequences()
    );
    assert_eq!(
        from_cdr::<Strings>(rclpy("Strings")).expect("Strings"),
        strings_msg()
    );
    assert_eq!(
        from_cdr::<WStrings>(rclpy("WStrings")).expect("WStrings"),
        wstrings_msg()
    );
}

/// Every kind of field, written out the way the generator emits it.
#[derive(Clone, Debug, PartialEq, Deserialize)]
struct Every {
    /// `string<=10 label`
    label: String,
    /// `string<=4[<=3] tags`
    tags: Vec<String>,
    /// `float64[40] samples`
    #[serde(with = "::horus_ros_msgs::runtime::array")]
    samples: [f64; 40],
    /// `string<=6[33] names`
    #[serde(deserialize_with = "::horus_ros_msgs::runtime::array::deserialize")]
    names: [String; 33],
    /// `wstring<=5 title`
    title: WString,
    /// `wstring[] notes`
    notes: Vec<WString>,
    /// `BasicTypes[<=2] items`
    items: Vec<BasicTypes>,
    /// `byte[64] raw`
    #[serde(deserialize_with = "::horus_ros_msgs::runtime::array::deserialize")]
    raw: [Byte; 64],
    /// `wchar letter` (IDL only)
    letter: u16,
}

impl Default for Every {
    fn default() -> Self {
        Self {
            label: String::new(),
            tags: Vec::new(),
            samples: default_array(),
            names: default_array(),
            title: WString::default(),
            notes: Vec::new(),
            items: Vec::new(),
            raw: default_array(),
            letter: 0,
        }
    }
}

impl Serialize for Every {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut s = serializer.serialize_struct("Every", 9)?;
        s.serialize_field("label", &Bounded::new(&self.label, "label", Some(10), None))?;
        s.serialize_field("tags", &Bounded::new(&self.tags, "tags", Some(4), Some(3)))?;
        s.serialize_field(
            "samples",
            &Bounded::new(&self.samples, "samples", None, None),
        )?;
        s.serialize_field("names", &Bounded::new(&self.names, "names", Some(6), None))?;
        s.serialize_field("title", &Bounded::new(&self.title, "title", Some(5), None))?;
        s.serialize_field("notes", &Bounded::new(&self.notes, "notes", None, None))?;
        s.serialize_field("items", &Bounded::new(&self.items, "items", None, Some(2)))?;
        s.serialize_field("raw", &Bounded::new(&self.raw, "raw", None, None))?;
        s.serialize_field("letter", &Bounded::new(&self.letter, "letter", None, None))?;
        s.end()
    }
}

impl Message for Every {
    const TYPE_NAME: &'static str = "horus_test/msg/Every";
    fn type_description() -> TypeDescription {
        DescriptionBuilder::new(Self::TYPE_NAME)
            .field_with::<String>("label", |t| t.bounded_string(10))
            .field_with::<Vec<String>>("tags", |t| t.bounded_string(4).bounded_sequence(3))
            .field::<[f64; 40]>("samples")
            .field_with::<[String; 33]>("names", |t| t.bounded_string(6))
            .field_with::<WString>("title", |t| t.bounded_string(5))
            .field::<Vec<WString>>("notes")
            .field_with::<Vec<BasicTypes>>("items", |t| t.bounded_sequence(2))
            .field::<[Byte; 64]>("raw")
            .field::<u16>("letter")
            .build()
    }
}

/// `Every[<=2] every`: violations inside nested messages name the whole path.
#[derive(Clone, Debug, PartialEq, Deserialize)]
struct Outer {
    every: Vec<Every>,
}

impl Serialize for Outer {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut s = serializer.serialize_struct("Outer", 1)?;
        s.serialize_field("every", &Bounded::new(&self.every, "every", None, Some(2)))?;
        s.end()
    }
}

fn every() -> Every {
    Every {
        label: "ten bytes!".into(),
        tags: strings(&["a", "bb", "cccc"]),
        samples: std::array::from_fn(|i| i as f64 * 0.5 - 3.0),
        names: std::array::from_fn(|i| format!("n{i}")),
        title: "ü😀ab".into(), // 5 UTF-16 units (😀 is two), 8 UTF-8 bytes
        notes: wstrings(&["first", "", "ハロー"]),
        items: vec![basic!(BasicTypes, 1), basic!(BasicTypes, 2)],
        raw: std::array::from_fn(|i| Byte(i as u8)),
        letter: 0x263a,
    }
}

/// The error of encoding `value`, which must be [`CdrError::BoundExceeded`].
fn bound_error<T: Serialize>(value: &T) -> BoundError {
    match to_cdr(value) {
        Err(CdrError::BoundExceeded(e)) => {
            assert!(take_bound_error().is_none(), "to_cdr leaves nothing behind");
            e
        }
        other => panic!("expected BoundExceeded, got {other:?}"),
    }
}

fn expect(field: &str, kind: BoundKind, bound: u64, length: u64) -> BoundError {
    BoundError {
        field: field.to_owned(),
        kind,
        bound,
        length,
    }
}

#[test]
fn every_kind_round_trips_at_the_bounds() {
    let v = every();
    let bytes = to_cdr(&v).expect("values at their bounds encode");
    assert_eq!(from_cdr::<Every>(&bytes).expect("decode"), v);
    let body = to_cdr_body(&v).expect("body");
    assert_eq!(bytes[4..], body[..]);
    let outer = Outer {
        every: vec![v.clone(), Every::default()],
    };
    let bytes = to_cdr(&outer).expect("encode outer");
    assert_eq!(from_cdr::<Outer>(&bytes).expect("decode outer"), outer);
}

#[test]
fn long_arrays_have_no_count() {
    #[derive(Debug, PartialEq, Deserialize)]
    struct Long {
        #[serde(with = "::horus_ros_msgs::runtime::array")]
        samples: [f64; 40],
        #[serde(with = "::horus_ros_msgs::runtime::array")]
        bytes: [u8; 33],
        tail: u32,
    }
    impl Serialize for Long {
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut s = serializer.serialize_struct("Long", 3)?;
            s.serialize_field(
                "samples",
                &Bounded::new(&self.samples, "samples", None, None),
            )?;
            s.serialize_field("bytes", &Bounded::new(&self.bytes, "bytes", None, None))?;
            s.serialize_field("tail", &Bounded::new(&self.tail, "tail", None, None))?;
            s.end()
        }
    }
    let v = Long {
        samples: std::array::from_fn(|i| i as f64),
        bytes: std::array::from_fn(|i| i as u8 + 1),
        tail: 0xdead_beef,
    };
    let bytes = to_cdr(&v).expect("encode");
    let mut expected = vec![0, 1, 0, 0];
    for i in 0..40 {
        expected.extend_from_slice(&f64::from(i).to_le_bytes());
    }
    expected.extend(1..=33_u8);
    expected.extend_from_slice(&[0, 0, 0]); // align the u32 to 4
    expected.extend_from_slice(&0xdead_beef_u32.to_le_bytes());
    assert_eq!(bytes, expected);
    assert_eq!(from_cdr::<Long>(&bytes).expect("decode"), v);
    // A short tuple is an error, not a panic.
    assert!(matches!(
        from_cdr::<Long>(&bytes[..100]),
        Err(CdrError::Decode(_))
    ));
}

#[test]
fn string_bound_counts_utf8_bytes() {
    let mut v = every();
    v.label = "elevenbytes".into();
    assert_eq!(bound_error(&v), expect("label", BoundKind::String, 10, 11));
    // 6 characters, 12 bytes.
    v.label = "ääääää".into();
    assert_eq!(bound_error(&v), expect("label", BoundKind::String, 10, 12));
}

#[test]
fn sequence_and_element_bounds() {
    let mut v = every();
    v.tags.push("d".into());
    assert_eq!(bound_error(&v), expect("tags", BoundKind::Sequence, 3, 4));
    let mut v = every();
    v.tags[1] = "fives".into();
    assert_eq!(bound_error(&v), expect("tags[1]", BoundKind::String, 4, 5));
    let mut v = every();
    v.names[32] = "seven!!".into();
    assert_eq!(
        bound_error(&v),
        expect("names[32]", BoundKind::String, 6, 7)
    );
    let mut v = every();
    v.items.push(basic!(BasicTypes, 3));
    assert_eq!(bound_error(&v), expect("items", BoundKind::Sequence, 2, 3));
}

#[test]
fn wstring_bound_counts_utf16_units() {
    let mut v = every();
    v.title = "😀😀😀".into(); // 3 characters, 6 units
    assert_eq!(bound_error(&v), expect("title", BoundKind::WString, 5, 6));
    // WStrings: wstring[<=3]
    let mut w = wstrings_msg();
    w.bounded_sequence_of_wstrings = wstrings(&["a", "b", "c", "d"]);
    assert_eq!(
        bound_error(&w),
        expect("bounded_sequence_of_wstrings", BoundKind::Sequence, 3, 4)
    );
}

#[test]
fn nested_violations_name_the_path() {
    let mut bad = every();
    bad.tags[0] = "too long".into();
    let outer = Outer {
        every: vec![every(), bad],
    };
    let err = bound_error(&outer);
    assert_eq!(err, expect("every[1].tags[0]", BoundKind::String, 4, 8));
    let mut bad = every();
    bad.label = "much too long".into();
    let outer = Outer { every: vec![bad] };
    assert_eq!(
        bound_error(&outer),
        expect("every[0].label", BoundKind::String, 10, 13)
    );
    let outer = Outer {
        every: vec![every(), every(), every()],
    };
    assert_eq!(
        bound_error(&outer),
        expect("every", BoundKind::Sequence, 2, 3)
    );
}

#[test]
fn bound_error_is_reported_once() {
    let mut v = every();
    v.label = "elevenbytes".into();
    let err = to_cdr_body(&v).expect_err("over the bound");
    assert!(matches!(err, CdrError::BoundExceeded(_)));
    assert_eq!(
        err.to_string(),
        "field 'label': string of 11 bytes exceeds its bound of 10 bytes"
    );
    assert!(err.source().is_none(), "the cause is in the message only");
    assert!(take_bound_error().is_none());
    let mut v = every();
    v.title = "wide title".into();
    assert_eq!(
        to_cdr(&v).expect_err("over").to_string(),
        "field 'title': wstring of 10 UTF-16 units exceeds its bound of 5 UTF-16 units"
    );
    let mut v = every();
    v.items = vec![basic!(BasicTypes, 0); 5];
    assert_eq!(
        to_cdr(&v).expect_err("over").to_string(),
        "field 'items': sequence of 5 elements exceeds its bound of 2 elements"
    );
}

#[test]
fn other_serializers_see_the_message_and_a_stale_error_is_dropped() {
    let mut v = every();
    v.label = "elevenbytes".into();
    // serde_json: the serializer's own error carries the message; the typed error waits.
    let err = serde_json::to_string(&v).expect_err("over the bound");
    assert!(err.to_string().contains("field 'label'"), "{err}");
    // The next encode starts clean and succeeds.
    to_cdr(&every()).expect("a fresh encode ignores the stale violation");
    assert!(take_bound_error().is_none());
}

#[test]
fn wstring_api_and_json() {
    let w = WString::from("ü😀");
    assert_eq!(&*w, "ü😀");
    assert_eq!(w.utf16_len(), 3);
    assert_eq!(w.to_string(), "ü😀");
    assert_eq!(WString::from(String::from("x")), WString("x".into()));
    assert_eq!(serde_json::to_string(&w).expect("json"), "\"ü😀\"");
    assert_eq!(serde_json::from_str::<WString>("\"ü😀\"").expect("json"), w);
    assert_eq!(
        <WString as horus_ros_msgs::RosField>::field_type().type_id,
        horus_ros_msgs::FieldType::FIELD_TYPE_WSTRING
    );
}

#[test]
fn wstring_decode_rejects_bad_units() {
    #[derive(Debug, Deserialize)]
    struct One {
        #[allow(dead_code)]
        w: WString,
    }
    let payload = |units: &[u32]| -> Vec<u8> {
        let mut b = vec![0, 1, 0, 0];
        b.extend_from_slice(&u32::try_from(units.len()).expect("len").to_le_bytes());
        for u in units {
            b.extend_from_slice(&u.to_le_bytes());
        }
        b
    };
    assert!(from_cdr::<One>(&payload(&[0x61, 0xd83d, 0xde00])).is_ok());
    // Above the UTF-16 unit range (rosidl_typesupport_fastrtps rejects it too).
    assert!(matches!(
        from_cdr::<One>(&payload(&[0x1_0000])),
        Err(CdrError::Decode(_))
    ));
    // An unpaired surrogate.
    assert!(matches!(
        from_cdr::<One>(&payload(&[0xd83d, 0x61])),
        Err(CdrError::Decode(_))
    ));
    // A count beyond the bytes: an error, not an allocation.
    let mut huge = vec![0, 1, 0, 0];
    huge.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(from_cdr::<One>(&huge), Err(CdrError::Decode(_))));
}

#[test]
fn default_array_any_length() {
    let a: [String; 50] = default_array();
    assert!(a.iter().all(String::is_empty));
    let v = Every::default();
    assert_eq!(v.samples, [0.0; 40]);
    let bytes = to_cdr(&v).expect("encode");
    assert_eq!(from_cdr::<Every>(&bytes).expect("decode"), v);
}
