//! The `.idl` parser against rosidl_parser (jazzy) itself: every `.idl` file of the venv's
//! `share/*/{msg,srv,action}/` and a few hand-written ones, parsed by both and compared as JSON
//! (`tests/rosidl_dump.py` writes rosidl_parser's side); then malformed inputs and where their
//! errors point.
//!
//! The Python is `HORUS_ROS_INTEROP_PYTHON`, else the workspace's venv (`scripts/setup`), as
//! the other interop tests find it.

use std::path::{Path, PathBuf};
use std::process::Command;

use horus_ros_codegen::definition::{
    BaseType, Constant, Container, Field, FieldType, Interface, Literal, Message, Primitive, Value,
};
use horus_ros_codegen::idl::parse_idl;
use serde_json::{json, Value as Json};

use horus_ros_test_support::jazzy::python;

/// rosidl_parser's parse of `files` (all of the venv's share if none), one JSON per file.
fn rosidl_dump(files: &[PathBuf]) -> Vec<Json> {
    let py = python();
    assert!(
        py.exists(),
        "{} missing: run scripts/setup or set HORUS_ROS_INTEROP_PYTHON",
        py.display()
    );
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rosidl_dump.py");
    let out = Command::new(&py)
        .arg(script)
        .args(files)
        .output()
        .expect("the Python runs");
    assert!(
        out.status.success(),
        "rosidl_dump.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .expect("UTF-8 output")
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect()
}

/// rosidl_parser's name of a basic type (`BasicType.typename`).
fn idl_name(p: Primitive) -> &'static str {
    match p {
        Primitive::Bool => "boolean",
        Primitive::Byte => "octet",
        Primitive::Char => "char",
        Primitive::WChar => "wchar",
        Primitive::Float32 => "float",
        Primitive::Float64 => "double",
        Primitive::LongDouble => "long double",
        other => other.msg_name(),
    }
}

fn base_json(b: &BaseType) -> Json {
    match b {
        BaseType::Primitive(p) => json!({ "primitive": idl_name(*p) }),
        BaseType::String(n) => json!({ "string": n }),
        BaseType::WString(n) => json!({ "wstring": n }),
        BaseType::Named(n) => json!({ "named": n.to_string() }),
    }
}

fn type_json(t: &FieldType) -> Json {
    let (container, size) = match t.container {
        Container::Single => ("single", None),
        Container::Array(n) => ("array", Some(n)),
        Container::UnboundedSequence => ("sequence", None),
        Container::BoundedSequence(n) => ("bounded_sequence", Some(n)),
    };
    json!({ "base": base_json(&t.base), "container": container, "size": size })
}

fn literal_json(l: &Literal) -> Json {
    match l {
        Literal::Bool(b) => json!({ "bool": b }),
        Literal::Int(i) => json!({ "int": i.to_string() }),
        Literal::Float(f) => json!({ "float": f.to_bits().to_string() }),
        Literal::String(s) => json!({ "string": s }),
    }
}

fn field_json(f: &Field) -> Json {
    let default = f.default.as_ref().map(|d| match d {
        Value::Scalar(l) => json!({ "scalar": literal_json(l) }),
        Value::Array(items) => {
            json!({ "array": items.iter().map(literal_json).collect::<Vec<_>>() })
        }
    });
    json!({
        "name": f.name,
        "type": type_json(&f.ty),
        "default": default,
        "comment": f.comment,
        "unit": f.unit,
    })
}

fn constant_json(c: &Constant) -> Json {
    json!({
        "name": c.name,
        "type": base_json(&c.ty),
        "value": literal_json(&c.value),
        "comment": c.comment,
    })
}

fn message_json(m: &Message) -> Json {
    json!({
        "name": m.name.to_string(),
        "comment": m.comment,
        "fields": m.fields.iter().map(field_json).collect::<Vec<_>>(),
        "constants": m.constants.iter().map(constant_json).collect::<Vec<_>>(),
    })
}

fn interface_json(file: &Path, i: &Interface) -> Json {
    let (kind, messages) = match i {
        Interface::Message(m) => ("message", vec![m]),
        Interface::Service(s) => ("service", vec![&s.request, &s.response]),
        Interface::Action(a) => ("action", vec![&a.goal, &a.result, &a.feedback]),
    };
    json!({
        "file": file.display().to_string(),
        "kind": kind,
        "name": i.name().to_string(),
        "messages": messages.into_iter().map(message_json).collect::<Vec<_>>(),
    })
}

#[derive(Default, Debug)]
struct Counts {
    files: usize,
    types: usize,
    fields: usize,
    constants: usize,
    defaults: usize,
    comments: usize,
}

/// Parses each dumped file with ours and compares; counts what was compared.
fn compare(expected: &[Json]) -> Counts {
    let mut counts = Counts::default();
    let mut failures = Vec::new();
    for want in expected {
        let file = PathBuf::from(want["file"].as_str().expect("a file name"));
        let text = std::fs::read_to_string(&file).expect("the .idl file reads");
        let got = match parse_idl(&file, &text) {
            Ok(interface) => interface_json(&file, &interface),
            Err(e) => {
                failures.push(format!("{e}"));
                continue;
            }
        };
        if &got != want {
            failures.push(format!(
                "{}:\n ours:    {got}\n rosidl:  {want}",
                file.display()
            ));
            continue;
        }
        counts.files += 1;
        for m in want["messages"].as_array().expect("messages") {
            counts.types += 1;
            let fields = m["fields"].as_array().expect("fields");
            counts.fields += fields.len();
            counts.defaults += fields.iter().filter(|f| !f["default"].is_null()).count();
            counts.comments += fields
                .iter()
                .filter(|f| f["comment"].as_array().is_some_and(|c| !c.is_empty()))
                .count();
            counts.constants += m["constants"].as_array().expect("constants").len();
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} files differ:\n{}",
        failures.len(),
        expected.len(),
        failures.join("\n")
    );
    counts
}

#[test]
fn every_installed_idl_file_parses_as_rosidl_parser_parses_it() {
    let expected = rosidl_dump(&[]);
    let counts = compare(&expected);
    eprintln!("compared with rosidl_parser: {counts:?}");
    // Jazzy's message packages of the venv: 199 files, over 230 types.
    assert!(counts.files >= 190, "too few .idl files found: {counts:?}");
    assert!(counts.types >= 220, "too few types: {counts:?}");
    for package in [
        "std_msgs",
        "geometry_msgs",
        "sensor_msgs",
        "nav_msgs",
        "test_msgs",
    ] {
        assert!(
            expected
                .iter()
                .any(|j| j["name"].as_str().is_some_and(|n| n.starts_with(package))),
            "no {package} file"
        );
    }
}

/// What rosidl_adapter never writes but rosidl_parser reads: every basic type name, `char` and
/// `wchar`, wide strings, named constants' modules, typedefs of sequences, multi-declarator
/// members, escapes, other annotations.
const HAND_WRITTEN: &[(&str, &str)] = &[
    (
        "hand_msgs/msg/AllTypes.idl",
        r#"
#include <hand_msgs/msg/Other.idl>
#include "builtin_interfaces/msg/Time.idl"
/* a block
   comment */
module hand_msgs {
  module msg {
    typedef sequence<double, 4> seq4;
    typedef hand_msgs::msg::Other Other_t;
    typedef Other_t Other_t__2[2];
    typedef long double ld__3[3];
    module AllTypes_Constants {
      @verbatim (language="comment", text="first line\nsecond" "\r\nthird\n")
      const unsigned long long BIG = 18446744073709551615;
      const long long SMALL = -9223372036854775808;
      const short HEX = 32767;
      const unsigned short OCT = 511;
      const char C = 65;
      const wchar WC = 66;
      const boolean YES = TRUE;
      const float F = 1;
      const double D = -.5e-3;
      const double FIXED = 2.5d;
      const string S = "tab\there \"q\" back\\slash \101\x42 \? \u0041";
      const wstring WS = L"w\u00e9\u263a" L"!";
      const string<3> LONGER = "longer than three";
    };
    @verbatim (language="comment", text="the struct")
    @topic
    struct AllTypes {
      @key
      boolean b;
      octet o;
      char c;
      wchar w;
      float f32;
      double f64;
      long double fld;
      short s16;
      unsigned short u16;
      long s32;
      unsigned long u32;
      long long s64;
      unsigned long long u64;
      int8 i8; uint8 u8; int16 i16; uint16 uu16; int32 i32; uint32 uu32; int64 i64; uint64 uu64;
      string s;
      string<5> bs;
      wstring ws;
      wstring<7> bws;
      @default (value=L"wide")
      wstring wdef;
      sequence<int32> seq;
      sequence<string<3>, 9> bseq;
      sequence<Other_t> others;
      ::hand_msgs::msg::Other abs_other;
      seq4 typedef_seq;
      Other_t__2 other_pair;
      ld__3 lds;
      double x, y, z;
      @default (value=-7) @unit (value="m/s") @range (min=1, max=2)
      int16 with_default;
      @default (value=3)
      double float_from_int;
      @default (value="(1, -2, 3)")
      sequence<double, 5> floats_from_ints;
      @default (value="('a', \"b'c\", 'd\\\\e')")
      string names[3];
      @default (value="[True, False]")
      sequence<boolean> flags;
      @default (value="()")
      sequence<int8> none;
      @default (value="(1.125,)")
      float one[1];
      @default (value=16)
      uint8 sixteen;
    };
  };
};
"#,
    ),
    (
        "hand_msgs/srv/Ask.idl",
        r#"
module hand_msgs { module srv {
  module Ask_Request_Constants { const int8 MODE = -1; };
  struct Ask_Request { uint8 structure_needs_at_least_one_member; };
  struct Ask_Response { @verbatim (language="comment", text="answer") string answer; };
}; };
"#,
    ),
    (
        "hand_msgs/action/Go.idl",
        r#"
module hand_msgs { module action {
  struct Go_Goal { int32 target; };
  struct Go_Result { sequence<int32> path; };
  @verbatim (language="other", text="not a comment")
  struct Go_Feedback { float progress; };
}; };
"#,
    ),
];

#[test]
fn hand_written_idl_files_parse_as_rosidl_parser_parses_them() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("idl_hand_written");
    let _ = std::fs::remove_dir_all(&dir);
    let mut files = Vec::new();
    for (path, text) in HAND_WRITTEN {
        let file = dir.join(path);
        std::fs::create_dir_all(file.parent().expect("a parent")).expect("the directory");
        std::fs::write(&file, text).expect("the file writes");
        files.push(file.canonicalize().expect("the file exists"));
    }
    let expected = rosidl_dump(&files);
    assert_eq!(expected.len(), HAND_WRITTEN.len());
    let counts = compare(&expected);
    eprintln!("hand-written, compared with rosidl_parser: {counts:?}");
}

// ---------------------------------------------------------------------------------------------
// Malformed input

/// The error of parsing `text`: `(line, column, message)`.
fn error_of(text: &str) -> (usize, usize, String) {
    let e = parse_idl(Path::new("bad.idl"), text).expect_err("a parse error");
    assert_eq!(e.location.file, Path::new("bad.idl"));
    (e.location.line, e.location.column, e.message)
}

fn assert_error(text: &str, line: usize, column: usize, message: &str) {
    let (l, c, m) = error_of(text);
    assert!(
        (l, c) == (line, column) && m.contains(message),
        "expected {line}:{column} `{message}`, got {l}:{c} `{m}` for:\n{text}"
    );
}

fn wrap(body: &str) -> String {
    format!("module p {{\n  module msg {{\n{body}\n  }};\n}};\n")
}

#[test]
fn unterminated_string() {
    assert_error(
        &wrap("    struct S {\n      @default (value=\"abc)\n      string s;\n    };"),
        4,
        23,
        "unterminated string literal",
    );
    assert_error(
        "module p { const string X = \"a\\\"",
        1,
        29,
        "unterminated string",
    );
}

#[test]
fn unknown_type() {
    assert_error(
        &wrap("    struct S {\n      int32 a;\n      Foo b;\n    };"),
        5,
        7,
        "unknown type `Foo`",
    );
    assert_error(
        &wrap("    struct S {\n      p::Foo b;\n    };"),
        4,
        7,
        "package::namespace::Name",
    );
}

#[test]
fn missing_semicolon() {
    assert_error(
        &wrap("    struct S {\n      int32 a\n      int32 b;\n    };"),
        5,
        7,
        "expected `;`, found `int32`",
    );
    assert_error(
        &wrap("    struct S {\n      int32 a;\n    }"),
        6,
        3,
        "expected `;`, found `}`",
    );
}

#[test]
fn bad_array_size() {
    assert_error(
        &wrap("    struct S {\n      double a[0];\n    };"),
        4,
        16,
        "expected an array size (a positive integer), found 0",
    );
    assert_error(
        &wrap("    struct S {\n      double a[-2];\n    };"),
        4,
        16,
        "array size",
    );
    assert_error(
        &wrap("    struct S {\n      double a[N];\n    };"),
        4,
        16,
        "array size",
    );
    assert_error(
        &wrap("    struct S {\n      double a[2][3];\n    };"),
        4,
        18,
        "multidimensional",
    );
    assert_error(
        &wrap("    struct S {\n      sequence<double, 0> a;\n    };"),
        4,
        24,
        "sequence bound",
    );
}

#[test]
fn unbalanced_braces() {
    assert_error(
        "module p {\n  module msg {\n    struct S { int32 a; };\n  };\n",
        5,
        1,
        "expected `}`, found end of file",
    );
    assert_error(
        "module p {\n  module msg {\n    struct S { int32 a; };\n  };\n};\n};\n",
        6,
        1,
        "expected `module`, `const`, `typedef`, `struct` or `enum`, found `}`",
    );
}

#[test]
fn other_errors() {
    assert_error("", 1, 1, "expected `module`");
    assert_error("module p { module msg { }; };", 1, 25, "expected `module`");
    assert_error("module p { /* open", 1, 12, "unterminated comment");
    assert_error("#define X", 1, 1, "#include");
    assert_error(
        "module p { const int8 X = 'a'; };",
        1,
        27,
        "character literals",
    );
    assert_error(
        "module p { const int8 X = 300; };",
        1,
        27,
        "out of the range of int8",
    );
    assert_error("module p { const int8 X = 1 + 2; };", 1, 29, "expected `;`");
    assert_error("module p { const int8 X = 12ab; };", 1, 27, "malformed");
    assert_error(
        "module p { const string X = \"\\x4\"; };",
        1,
        29,
        "truncated",
    );
    assert_error("module p { module msg { struct S { int32 a; }; }; };\nmodule q { module msg { struct T { int32 a; }; }; };", 1, 32, "`Name_Request`");
    assert_error(
        "module p { struct S { int32 a; }; };",
        1,
        19,
        "module <package>",
    );
    assert_error(
        &wrap("    struct S {\n      @default (value=\"(1, 2)\")\n      int32 a[3];\n    };"),
        4,
        23,
        "2 default values for an array of 3",
    );
    assert_error(
        &wrap("    struct S {\n      @default (value=1.5)\n      int32 a;\n    };"),
        4,
        23,
        "expected a literal of type int32",
    );
    assert_error(
        &wrap("    typedef A B;\n    typedef B A;\n    struct S {\n      A a;\n    };"),
        6,
        7,
        "refers to itself",
    );
}

/// The grammar's octal and hexadecimal literals (which rosidl_parser's `get_const_expr_value`
/// then refuses) are integers here.
#[test]
fn octal_and_hexadecimal_literals() {
    let text = wrap(
        "    module S_Constants { const short H = -0x7fFF; const uint16 O = 0777; };\n    struct S {\n      @default (value=0X10)\n      uint8 a;\n      @default (value=010)\n      float b;\n    };",
    );
    let Interface::Message(m) = parse_idl(Path::new("n.idl"), &text).expect("parses") else {
        panic!("a message");
    };
    let values: Vec<&Literal> = m.constants.iter().map(|c| &c.value).collect();
    assert_eq!(values, [&Literal::Int(-0x7fff), &Literal::Int(0o777)]);
    assert_eq!(m.fields[0].default, Some(Value::Scalar(Literal::Int(16))));
    assert_eq!(
        m.fields[1].default,
        Some(Value::Scalar(Literal::Float(8.0)))
    );
}

#[test]
fn a_message_with_only_the_placeholder_member_has_no_fields() {
    let text = wrap("    struct Empty {\n      uint8 structure_needs_at_least_one_member;\n    };");
    let Interface::Message(m) = parse_idl(Path::new("e.idl"), &text).expect("parses") else {
        panic!("a message");
    };
    assert_eq!(m.name.to_string(), "p/msg/Empty");
    assert!(m.fields.is_empty());
}
