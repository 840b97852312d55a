//! `horus-ros interface show` (ros2interface jazzy `verb/show.py`): the interface file's lines,
//! each nested type's definition printed after the field that uses it, one tab deeper; comments
//! and blank lines of the type itself unless `--no-comments`, of nested types only with
//! `--all-comments`.
//!
//! ros2cli decides what a line is by parsing it alone with rosidl_adapter (jazzy 4.6
//! `parse_message_string`): [`classify`] does the same, quirks included (a line holding only `#`
//! is not a comment; a trailing comment is cut at the character before its text after
//! rosidl_adapter dedents it, so `int32 x # c` prints as `int32 x #` with `--no-comments`).
//!
//! A type without a file (compiled into horus-ros, or read off a node with `--from-graph`) is
//! shown from its type description: one `type name [default]` line a field, in `.msg` syntax,
//! nested types expanded the same way; a description has neither comments nor constants.

use std::io::IsTerminal;
use std::sync::OnceLock;

use regex::Regex;
use serde_json::json;

use super::catalog::Catalog;
use super::definition::{self, Definition, TypeSource};
use crate::dynamic::{Container, Elem, FieldTy, Schema};
use crate::verb::names::print_json;
use crate::{CliError, Global};

/// Arguments of `interface show`.
#[derive(Debug, clap::Args)]
pub struct ShowArgs {
    /// Show an interface definition (e.g. 'example_interfaces/msg/String'). Passing '-' reads
    /// the argument from stdin (e.g. 'horus-ros topic type /chatter | horus-ros interface show
    /// -').
    #[arg(value_name = "TYPE")]
    pub type_name: String,
    /// Show all comments, including for nested interface definitions.
    #[arg(long, conflicts_with = "no_comments")]
    pub all_comments: bool,
    /// Show no comments or whitespace.
    #[arg(long)]
    pub no_comments: bool,
    /// Where the type comes from.
    #[command(flatten)]
    pub source: TypeSource,
}

/// ros2interface `ReadStdinPipe`: `-` is the first line of stdin, stripped; an empty value is
/// a usage error (exit 2).
pub fn read_type_argument(value: &str) -> Result<String, CliError> {
    let usage = |m: &str| CliError {
        message: format!("error: {m}"),
        code: 2,
    };
    let value = if value == "-" {
        if std::io::stdin().is_terminal() {
            return Err(usage("expected stdin pipe"));
        }
        let mut line = String::new();
        std::io::stdin()
            .read_line(&mut line)
            .map_err(|e| usage(&format!("cannot read stdin: {e}")))?;
        line.trim().to_owned()
    } else {
        value.to_owned()
    };
    if value.is_empty() {
        return Err(usage("the passed value is empty"));
    }
    Ok(value)
}

/// Runs `interface show`.
pub fn run(global: &Global, args: &ShowArgs) -> Result<(), CliError> {
    let type_name = read_type_argument(&args.type_name)?;
    let catalog = Catalog::from_env();
    let definition = args.source.definition(global, &catalog, &type_name)?;
    let mut out = String::new();
    let result = show(
        &catalog,
        &definition,
        Comments {
            own: !args.no_comments,
            nested: args.all_comments,
        },
        0,
        &mut out,
    );
    if global.json {
        result?;
        let mut doc = json!({
            "type": type_name,
            "origin": definition.origin().as_str(),
            "definition": out,
        });
        if let Definition::File { path, .. } = &definition {
            doc["path"] = json!(path.display().to_string());
        }
        return print_json(&doc);
    }
    // As ros2cli, what was printed before a failure (a nested type not found) stays printed.
    print!("{out}");
    result
}

/// Which comments to print.
#[derive(Clone, Copy, Debug)]
pub struct Comments {
    /// Of this type.
    pub own: bool,
    /// Of nested types.
    pub nested: bool,
}

/// Appends the definition (ros2interface `_show_interface`) to `out`.
pub fn show(
    catalog: &Catalog,
    definition: &Definition,
    comments: Comments,
    indent: usize,
    out: &mut String,
) -> Result<(), CliError> {
    match definition {
        Definition::File { package, path } => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| CliError::new(format!("{}: {e}", path.display())))?;
            // Python's text mode reads `\r\n` and `\r` as `\n`.
            let text = text.replace("\r\n", "\n").replace('\r', "\n");
            for line in text.lines() {
                let line = line.trim_end();
                let info = classify(package, line);
                print_line(line, &info, comments.own, indent, out);
                if let Some(nested) = &info.nested {
                    let nested_definition = definition::resolve(catalog, nested)?;
                    show(
                        catalog,
                        &nested_definition,
                        Comments {
                            own: comments.nested,
                            nested: comments.nested,
                        },
                        indent + 1,
                        out,
                    )?;
                }
            }
            Ok(())
        }
        Definition::Described { schema, parts, .. } => {
            for (i, part) in parts.iter().enumerate() {
                if i > 0 {
                    push_line(out, indent, "---");
                }
                show_struct(schema, part, indent, out);
            }
            Ok(())
        }
    }
}

/// One `type name [default]` line a field of struct `name`, nested types expanded.
fn show_struct(schema: &Schema, name: &str, indent: usize, out: &mut String) {
    let Ok(s) = schema.get(name) else {
        return;
    };
    if s.is_empty_placeholder() {
        return;
    }
    for m in &s.members {
        let mut line = format!("{} {}", msg_type(&m.ty), m.name);
        if !m.default.is_empty() {
            line.push(' ');
            line.push_str(&m.default);
        }
        push_line(out, indent, &line);
        if let Elem::Nested(n) = &m.ty.elem {
            show_struct(schema, n, indent + 1, out);
        }
    }
}

/// A field type in `.msg` syntax (`pkg/Name` for a nested `pkg/msg/Name`).
fn msg_type(ty: &FieldTy) -> String {
    let elem = match &ty.elem {
        Elem::Bool => "bool".to_owned(),
        Elem::Byte => "byte".to_owned(),
        Elem::Char => "char".to_owned(),
        Elem::WChar => "wchar".to_owned(),
        Elem::Int { bits, signed } => format!("{}int{bits}", if *signed { "" } else { "u" }),
        Elem::F32 => "float32".to_owned(),
        Elem::F64 => "float64".to_owned(),
        Elem::LongDouble => "long double".to_owned(),
        Elem::Str(None) => "string".to_owned(),
        Elem::Str(Some(n)) => format!("string<={n}"),
        Elem::WStr(None) => "wstring".to_owned(),
        Elem::WStr(Some(n)) => format!("wstring<={n}"),
        Elem::Nested(n) => match n.split('/').collect::<Vec<_>>()[..] {
            [package, _, name] => format!("{package}/{name}"),
            _ => n.clone(),
        },
    };
    match ty.container {
        Container::Single => elem,
        Container::Array(n) => format!("{elem}[{n}]"),
        Container::Sequence(None) => format!("{elem}[]"),
        Container::Sequence(Some(n)) => format!("{elem}[<={n}]"),
    }
}

fn push_line(out: &mut String, indent: usize, text: &str) {
    for _ in 0..indent {
        out.push('\t');
    }
    out.push_str(text);
    out.push('\n');
}

/// What rosidl_adapter makes of one line alone (ros2interface `InterfaceTextLine`).
#[derive(Debug, Default, PartialEq, Eq)]
pub struct LineInfo {
    /// `is_comment()`: a `#` line whose comment survives rosidl_adapter's `process_comments`.
    pub comment: bool,
    /// `trailing_comment`: the comment of a field or constant line, as processed.
    pub trailing: Option<String>,
    /// `nested_type`: `pkg/msg/Name` of a field of a non-primitive type.
    pub nested: Option<String>,
}

/// rosidl_adapter `PRIMITIVE_TYPES`.
const PRIMITIVE_TYPES: &[&str] = &[
    "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16", "int32",
    "uint32", "int64", "uint64", "string", "wstring", "duration", "time",
];

/// rosidl_adapter `process_comments` of a one-line comment: the unit in brackets removed when
/// there is exactly one, then nothing if empty, else the line dedented.
fn process_comment(comment: &str) -> Option<String> {
    static UNIT: OnceLock<Option<Regex>> = OnceLock::new();
    let unit = UNIT.get_or_init(|| Regex::new(r"(\s*\[([^,\]]+)\])").ok());
    let mut comment = comment.to_owned();
    if let Some(unit) = unit {
        let matches: Vec<String> = unit
            .find_iter(&comment)
            .map(|m| m.as_str().to_owned())
            .collect();
        if let [one] = &matches[..] {
            comment = comment.replace(one.as_str(), "");
        }
    }
    if comment.is_empty() {
        return None;
    }
    // textwrap.dedent of one line: its leading spaces and tabs.
    Some(comment.trim_start_matches([' ', '\t']).to_owned())
}

/// The `pkg/msg/Name` of a field type (ros2interface `nested_type`: rosidl_adapter `Type` with
/// the file's package as context), `None` for a primitive one.
fn nested_type(package: &str, type_string: &str) -> Option<String> {
    let base = type_string.split('[').next().unwrap_or(type_string);
    if PRIMITIVE_TYPES.contains(&base)
        || base.starts_with("string<=")
        || base.starts_with("wstring<=")
    {
        return None;
    }
    match base.split('/').collect::<Vec<_>>()[..] {
        [name] if !name.is_empty() => Some(format!("{package}/msg/{name}")),
        [pkg, name] if !pkg.is_empty() && !name.is_empty() => Some(format!("{pkg}/msg/{name}")),
        _ => None,
    }
}

/// What one line (right-stripped) is, as ros2interface learns it from rosidl_adapter's
/// `parse_message_string` of that line alone.
pub fn classify(package: &str, line: &str) -> LineInfo {
    if line == "---" {
        return LineInfo::default();
    }
    let line = line.replace('\t', " ");
    if line.is_empty() {
        return LineInfo::default();
    }
    // A file-level comment line.
    if let Some(rest) = line.strip_prefix('#') {
        return LineInfo {
            comment: process_comment(rest.trim_start_matches('#')).is_some(),
            ..LineInfo::default()
        };
    }
    let (body, comment) = match line.find('#') {
        Some(i) => (&line[..i], Some(line[i..].trim_start_matches('#'))),
        None => (line.as_str(), None),
    };
    // An indented comment line: no field, no constant, not a comment either.
    if comment.is_some() && body.trim().is_empty() {
        return LineInfo::default();
    }
    let body = body.trim_end();
    let (type_string, rest) = body.split_once(' ').unwrap_or((body, ""));
    if rest.trim_start().is_empty() {
        return LineInfo::default();
    }
    let constant = rest.contains('=');
    LineInfo {
        comment: false,
        trailing: comment.and_then(process_comment),
        nested: if constant {
            None
        } else {
            nested_type(package, type_string)
        },
    }
}

/// ros2interface `_print_interface_line`.
fn print_line(text: &str, info: &LineInfo, show_comments: bool, indent: usize, out: &mut String) {
    let mut text = text.to_owned();
    if !show_comments {
        if text.is_empty() || info.comment {
            return;
        }
        if let Some(trailing) = &info.trailing {
            // `text[:text.find(trailing) - 1].strip()`, with Python's indexing (by character;
            // a negative end counts from the end).
            let chars: Vec<char> = text.chars().collect();
            let wanted: Vec<char> = trailing.chars().collect();
            let found = if wanted.is_empty() {
                Some(0)
            } else {
                chars
                    .windows(wanted.len())
                    .position(|w| w == wanted.as_slice())
            };
            let start = found.map_or(-1, |i| i as isize);
            let end = start - 1;
            let end = if end < 0 {
                (chars.len() as isize + end).max(0) as usize
            } else {
                end as usize
            };
            text = chars[..end.min(chars.len())]
                .iter()
                .collect::<String>()
                .trim()
                .to_owned();
        }
    }
    if text.is_empty() {
        out.push('\n');
    } else {
        push_line(out, indent, &text);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_classified_as_rosidl_adapter_parses_them_alone() {
        let c = |l: &str| classify("geometry_msgs", l);
        assert!(c("# A comment").comment);
        assert!(!c("#").comment);
        assert!(!c("# [m]").comment);
        assert_eq!(c("  # indented"), LineInfo::default());
        assert_eq!(
            c("Point position # where [m]"),
            LineInfo {
                comment: false,
                trailing: Some("where".to_owned()),
                nested: Some("geometry_msgs/msg/Point".to_owned()),
            }
        );
        assert_eq!(
            c("std_msgs/Header[<=3] headers").nested.as_deref(),
            Some("std_msgs/msg/Header")
        );
        assert_eq!(c("string<=5 s").nested, None);
        assert_eq!(c("int32 X=1 # c").trailing.as_deref(), Some("c"));
        assert_eq!(c("int32 X=1").nested, None);
        assert_eq!(c("int32 x #  [m]").trailing, None);
    }

    #[test]
    fn trailing_comments_are_cut_as_ros2cli_cuts_them() {
        let cut = |l: &str| {
            let mut out = String::new();
            print_line(l, &classify("p", l), false, 1, &mut out);
            out
        };
        assert_eq!(cut("bool B=true # Comment"), "\tbool B=true #\n");
        assert_eq!(cut("float32 a   # start [rad]"), "\tfloat32 a   #\n");
        assert_eq!(cut("int32 x ## c"), "\tint32 x ##\n");
        assert_eq!(cut("int32 x # a\tb"), "\tint32 x # a\n");
        assert_eq!(cut("# only"), "");
        assert_eq!(cut("#"), "\t#\n");
        assert_eq!(cut(""), "");
    }
}
