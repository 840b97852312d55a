//! `.msg`/`.srv`/`.action` parsing: what rosidl_adapter accepts, and errors that name the line,
//! the column and what was expected.

use std::path::Path;

use horus_ros_codegen::definition::{BaseType, Container, Literal, Primitive, Value};
use horus_ros_codegen::msg::{parse_action, parse_message, parse_service};

fn error(text: &str) -> String {
    parse_message("pkg", "Msg", Path::new("Msg.msg"), text)
        .expect_err("must not parse")
        .to_string()
}

#[test]
fn fields_constants_defaults_comments_and_units() {
    let text = "# The file's comment.\n\nint32 A=-3  # a constant\nstring S = 'x y'\n# The speed.\nfloat64 speed 1.5  # [m/s]\n  # more about speed\nstring<=4[<=2] tags ['ab', \"c,d\"]\nbyte b 0x1F\nchar c 65\ntime t\n";
    let m = parse_message("pkg", "Msg", Path::new("Msg.msg"), text).expect("parses");
    // Comments are dedented (rosidl_adapter `process_comments`).
    assert_eq!(m.comment, vec!["The file's comment."]);
    assert_eq!(m.constants[0].name, "A");
    assert_eq!(m.constants[0].value, Literal::Int(-3));
    assert_eq!(m.constants[1].value, Literal::String("x y".into()));
    let speed = &m.fields[0];
    assert_eq!(speed.unit.as_deref(), Some("m/s"));
    // rosidl_adapter finds the unit with `\s*\[…\]` over the joined lines (here "\n [m/s]") and
    // removes that match line by line, so a unit after the first line stays in the text.
    assert_eq!(
        speed.comment,
        vec!["The speed.", "[m/s]", "more about speed"]
    );
    assert_eq!(speed.default, Some(Value::Scalar(Literal::Float(1.5))));
    let tags = &m.fields[1];
    assert_eq!(tags.ty.base, BaseType::String(Some(4)));
    assert_eq!(tags.ty.container, Container::BoundedSequence(2));
    assert_eq!(
        tags.default,
        Some(Value::Array(vec![
            Literal::String("ab".into()),
            Literal::String("c,d".into())
        ]))
    );
    assert_eq!(m.fields[2].ty.base, BaseType::Primitive(Primitive::Byte));
    assert_eq!(m.fields[2].default, Some(Value::Scalar(Literal::Int(31))));
    assert_eq!(m.fields[3].ty.base, BaseType::Primitive(Primitive::UInt8));
    assert!(
        matches!(&m.fields[4].ty.base, BaseType::Named(t) if t.to_string() == "builtin_interfaces/msg/Time")
    );
}

#[test]
fn errors_point_at_the_line_and_column() {
    assert_eq!(
        error("int32 a\nint32 x 3000000000\n"),
        "Msg.msg:2:9: value '3000000000' can not be converted to type 'int32': must be a valid integer value >= -2147483648 and <= 2147483647"
    );
    assert_eq!(
        error("int32[0] x\n"),
        "Msg.msg:1:7: the size of array type 'int32[0]' must be an integer > 0, optionally prefixed with '<='"
    );
    assert!(error("strin x\n").starts_with("Msg.msg:1:1: unknown type 'strin'"));
    assert!(error("int32\n").starts_with("Msg.msg:1:6: expected a name"));
    assert!(error("int32 Bad\n").starts_with("Msg.msg:1:7: 'Bad' is not a valid field name"));
    assert!(error("int32 a\nint32 a\n").starts_with("Msg.msg:2:7: duplicate field name 'a'"));
    assert!(error("int32[2] a [1]\n").contains("array must have exactly 2 elements, not 1"));
    assert!(error("bool b maybe\n").contains("must be either 'true' / '1' or 'false' / '0'"));
    assert!(error("string<=3 s 'four'\n").contains("must not exceed the maximum length of 3"));
    assert!(error("pkg/Header h 1\n").contains("non-primitive type"));
    let srv = parse_service("pkg", "Srv", Path::new("Srv.srv"), "int32 a\n").expect_err("no ---");
    assert!(srv.to_string().contains("split by one line '---'"), "{srv}");
    let action =
        parse_action("pkg", "Act", Path::new("Act.action"), "int32 a\n---\n").expect_err("one ---");
    assert!(action.to_string().contains("two lines '---'"), "{action}");
    assert!(parse_message("pkg", "bad_name", Path::new("x.msg"), "").is_err());
}

#[test]
fn an_empty_message_has_no_fields_and_a_service_two_parts() {
    let m = parse_message("pkg", "Empty", Path::new("Empty.msg"), "# only a comment\n")
        .expect("parses");
    assert!(m.fields.is_empty());
    let s = parse_service(
        "pkg",
        "Srv",
        Path::new("Srv.srv"),
        "int64 a\n---\nint64 sum\n",
    )
    .expect("parses");
    assert_eq!(s.request.name.to_string(), "pkg/srv/Srv_Request");
    assert_eq!(s.response.fields[0].name, "sum");
    let a = parse_action(
        "pkg",
        "Act",
        Path::new("Act.action"),
        "int32 order\n---\nint32[] seq\n---\nint32[] part\n",
    )
    .expect("parses");
    assert_eq!(a.feedback.name.to_string(), "pkg/action/Act_Feedback");
}
