//! `.msg`, `.srv` and `.action` files, parsed as rosidl_adapter (jazzy) `parser.py` parses them
//! (`parse_message_string`, `parse_service_string`, `parse_action_string`), into the
//! [`definition`](crate::definition) model that `.idl` files share.
//!
//! A line is `type name [default]` or `type NAME=value`, a `#` starts a comment; a `.srv` is two
//! messages split by a line `---`, an `.action` three. Names, types and values are checked as
//! rosidl_adapter checks them, and an error names the file, line and column.

use std::path::{Path, PathBuf};

use crate::definition::{
    Action, BaseType, Constant, Container, Field, FieldType, Interface, Literal, Message,
    NamedType, Primitive, Service, Value,
};
use crate::error::ParseError;

/// rosidl_adapter's `SERVICE_REQUEST_RESPONSE_SEPARATOR` (also between an action's parts).
const SEPARATOR: &str = "---";

/// Parses an interface file, by its extension: `.msg`, `.srv`, `.action` here, `.idl` with
/// [`crate::idl`]. The interface's name is the file's stem.
pub fn parse_file(package: &str, path: &Path) -> Result<Interface, ParseError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| ParseError::new(path, 0, 0, format!("cannot read the file: {e}")))?;
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default();
    match path.extension().and_then(|e| e.to_str()) {
        Some("msg") => parse_message(package, name, path, &text).map(Interface::Message),
        Some("srv") => parse_service(package, name, path, &text).map(Interface::Service),
        Some("action") => parse_action(package, name, path, &text).map(Interface::Action),
        Some("idl") => crate::idl::parse_idl(path, &text),
        _ => Err(ParseError::new(
            path,
            0,
            0,
            "expected a .msg, .srv, .action or .idl file",
        )),
    }
}

/// Parses the text of `package/msg/name` (`file` only names it in errors).
pub fn parse_message(
    package: &str,
    name: &str,
    file: &Path,
    text: &str,
) -> Result<Message, ParseError> {
    let lines: Vec<&str> = text.lines().collect();
    let source = Source::new(file, package);
    check_interface_name(&source, name, "msg")?;
    source.message(NamedType::new(package, "msg", name), &lines, 0)
}

/// Parses the text of `package/srv/name`: request and response split by `---`.
pub fn parse_service(
    package: &str,
    name: &str,
    file: &Path,
    text: &str,
) -> Result<Service, ParseError> {
    let source = Source::new(file, package);
    check_interface_name(&source, name, "srv")?;
    let service = NamedType::new(package, "srv", name);
    let parts = source.split(
        text,
        2,
        "a service has a request and a response split by one line '---'",
    )?;
    Ok(Service {
        request: source.message(service.with_suffix("_Request"), &parts[0].1, parts[0].0)?,
        response: source.message(service.with_suffix("_Response"), &parts[1].1, parts[1].0)?,
        name: service,
    })
}

/// Parses the text of `package/action/name`: goal, result and feedback split by `---`.
pub fn parse_action(
    package: &str,
    name: &str,
    file: &Path,
    text: &str,
) -> Result<Action, ParseError> {
    let source = Source::new(file, package);
    check_interface_name(&source, name, "action")?;
    let action = NamedType::new(package, "action", name);
    let parts = source.split(
        text,
        3,
        "an action has a goal, a result and a feedback split by two lines '---'",
    )?;
    Ok(Action {
        goal: source.message(action.with_suffix("_Goal"), &parts[0].1, parts[0].0)?,
        result: source.message(action.with_suffix("_Result"), &parts[1].1, parts[1].0)?,
        feedback: source.message(action.with_suffix("_Feedback"), &parts[2].1, parts[2].0)?,
        name: action,
    })
}

fn check_interface_name(source: &Source, name: &str, kind: &str) -> Result<(), ParseError> {
    if !is_valid_package_name(source.package) {
        return Err(source.error(
            0,
            0,
            format!(
                "'{}' is not a valid package name (lower case letters, digits and single '_')",
                source.package
            ),
        ));
    }
    if !is_valid_message_name(name) {
        return Err(source.error(
            0,
            0,
            format!("'{name}' is not a valid {kind} name (CamelCase: a capital letter, then letters and digits)"),
        ));
    }
    Ok(())
}

/// The file being parsed.
struct Source<'a> {
    file: PathBuf,
    package: &'a str,
}

/// One line of a message, after tabs became spaces: its 0-based index in the file and text.
type Lines<'a> = Vec<&'a str>;

/// The comment and element a line carries.
enum Element {
    Field(Field),
    Constant(Constant),
}

impl<'a> Source<'a> {
    fn new(file: &Path, package: &'a str) -> Self {
        Self {
            file: file.to_owned(),
            package,
        }
    }

    fn error(&self, line: usize, column: usize, message: impl Into<String>) -> ParseError {
        ParseError::new(&self.file, line, column, message)
    }

    /// Splits at lines that are exactly `---` into `parts` parts: each with the index of its
    /// first line.
    fn split<'t>(
        &self,
        text: &'t str,
        parts: usize,
        expected: &str,
    ) -> Result<Vec<(usize, Lines<'t>)>, ParseError> {
        let lines: Vec<&str> = text.lines().collect();
        let separators: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i] == SEPARATOR)
            .collect();
        if separators.len() != parts - 1 {
            let (line, found) = match separators.get(parts - 1) {
                Some(&extra) => (extra + 1, "one '---' too many".to_owned()),
                None => (lines.len().max(1), format!("{} '---'", separators.len())),
            };
            return Err(self.error(line, 1, format!("{expected}; found {found}")));
        }
        let mut out = Vec::with_capacity(parts);
        let mut start = 0;
        for end in separators.into_iter().chain(std::iter::once(lines.len())) {
            out.push((start, lines[start..end].to_vec()));
            start = end + 1;
        }
        Ok(out)
    }

    /// rosidl_adapter `parse_message_string`, over `lines` whose first is line `first` (0-based)
    /// of the file.
    fn message(
        &self,
        name: NamedType,
        lines: &[&str],
        first: usize,
    ) -> Result<Message, ParseError> {
        let mut fields: Vec<Field> = Vec::new();
        let mut constants: Vec<Constant> = Vec::new();
        // Which element the last definition line made: comments attach to it.
        let mut last: Option<(bool, usize)> = None;
        let mut pending: Vec<String> = Vec::new();

        // File-level comments: the leading lines that start with '#'.
        let body_start = lines
            .iter()
            .position(|l| !l.replace('\t', " ").starts_with('#'))
            .unwrap_or(lines.len());
        let message_comment: Vec<String> = lines[..body_start]
            .iter()
            .map(|l| l.replace('\t', " ").trim_start_matches('#').to_owned())
            .collect();

        for (i, raw) in lines.iter().enumerate().skip(body_start) {
            let line_no = first + i + 1;
            let expanded = raw.replace('\t', " ");
            let line = expanded.trim_end();
            if line.is_empty() {
                continue;
            }
            let (content, comment) = match line.find('#') {
                Some(at) => (
                    &line[..at],
                    Some(line[at..].trim_start_matches('#').to_owned()),
                ),
                None => (line, None),
            };
            if let Some(comment) = comment {
                if !content.is_empty() && content.trim().is_empty() {
                    // An indented comment line continues the previous element's comment.
                    if let Some((is_field, at)) = last {
                        if is_field {
                            fields[at].comment.push(comment);
                        } else {
                            constants[at].comment.push(comment);
                        }
                    }
                    continue;
                }
                pending.push(comment);
                if content.trim_end().is_empty() {
                    continue;
                }
            }
            let content = content.trim_end();
            let element = self.definition_line(content, line_no)?;
            let comments = std::mem::take(&mut pending);
            match element {
                Element::Field(mut f) => {
                    if fields.iter().any(|g| g.name == f.name) {
                        return Err(self.error(
                            line_no,
                            column_of(content, &f.name),
                            format!("duplicate field name '{}'", f.name),
                        ));
                    }
                    f.comment.extend(comments);
                    fields.push(f);
                    last = Some((true, fields.len() - 1));
                }
                Element::Constant(mut c) => {
                    if constants.iter().any(|d| d.name == c.name) {
                        return Err(self.error(
                            line_no,
                            column_of(content, &c.name),
                            format!("duplicate constant name '{}'", c.name),
                        ));
                    }
                    c.comment.extend(comments);
                    constants.push(c);
                    last = Some((false, constants.len() - 1));
                }
            }
        }

        let mut message = Message {
            name,
            fields,
            constants,
            comment: message_comment,
        };
        message.comment = process_comment(std::mem::take(&mut message.comment)).0;
        for f in &mut message.fields {
            let (comment, unit) = process_comment(std::mem::take(&mut f.comment));
            f.comment = comment;
            f.unit = unit;
        }
        for c in &mut message.constants {
            c.comment = process_comment(std::mem::take(&mut c.comment)).0;
        }
        Ok(message)
    }

    /// One `type name [default]` or `type NAME=value` line (comment removed, trailing spaces
    /// trimmed).
    fn definition_line(&self, content: &str, line_no: usize) -> Result<Element, ParseError> {
        let (type_string, rest) = content.split_once(' ').unwrap_or((content, ""));
        let rest_trimmed = rest.trim_start();
        let rest_col = content.len() - rest_trimmed.len() + 1;
        if rest_trimmed.is_empty() {
            return Err(self.error(
                line_no,
                content.len() + 1,
                format!("expected a name after the type '{type_string}'"),
            ));
        }
        if type_string.is_empty() {
            return Err(self.error(line_no, 1, "expected a type at the start of the line"));
        }
        if let Some(eq) = rest_trimmed.find('=') {
            let name = rest_trimmed[..eq].trim_end();
            let value = rest_trimmed[eq + 1..].trim_start();
            let value_col = content.len() - value.len() + 1;
            return self
                .constant(type_string, name, value, line_no, rest_col, value_col)
                .map(Element::Constant);
        }
        let (name, default) = rest_trimmed.split_once(' ').unwrap_or((rest_trimmed, ""));
        let default = default.trim_start();
        let default_col = content.len() - default.len() + 1;
        let ty = self.field_type(type_string, line_no, 1)?;
        if !is_valid_field_name(name) {
            return Err(self.error(
                line_no,
                rest_col,
                format!("'{name}' is not a valid field name (lower case letters, digits and single '_', starting with a letter)"),
            ));
        }
        let default = if default.is_empty() {
            None
        } else {
            Some(parse_value(&ty, default).map_err(|e| self.error(line_no, default_col, e))?)
        };
        Ok(Element::Field(Field {
            name: name.to_owned(),
            ty,
            default,
            comment: Vec::new(),
            unit: None,
        }))
    }

    fn constant(
        &self,
        type_string: &str,
        name: &str,
        value: &str,
        line_no: usize,
        name_col: usize,
        value_col: usize,
    ) -> Result<Constant, ParseError> {
        let ty = match primitive_base(type_string) {
            Some(BaseType::Named(_)) | None => {
                return Err(self.error(
                    line_no,
                    1,
                    format!("the constant type '{type_string}' must be a primitive type"),
                ))
            }
            Some(base) => base,
        };
        if !is_valid_constant_name(name) {
            return Err(self.error(
                line_no,
                name_col,
                format!("'{name}' is not a valid constant name (upper case letters, digits and single '_')"),
            ));
        }
        let value =
            parse_primitive_value(&ty, value).map_err(|e| self.error(line_no, value_col, e))?;
        Ok(Constant {
            name: name.to_owned(),
            ty,
            value,
            comment: Vec::new(),
        })
    }

    /// rosidl_adapter `Type(type_string, context_package_name)`.
    fn field_type(&self, s: &str, line_no: usize, col: usize) -> Result<FieldType, ParseError> {
        let (base_str, container) = if let Some(open) = s
            .strip_suffix(']')
            .and_then(|t| t.rfind('[').map(|i| (i, t)))
        {
            let (index, without_close) = open;
            let size = &without_close[index + 1..];
            let container = if size.is_empty() {
                Container::UnboundedSequence
            } else {
                let (bounded, digits) = match size.strip_prefix("<=") {
                    Some(d) => (true, d),
                    None => (false, size),
                };
                let n = parse_positive(digits).ok_or_else(|| {
                    self.error(
                        line_no,
                        col + index + 1,
                        format!("the size of array type '{s}' must be an integer > 0, optionally prefixed with '<='"),
                    )
                })?;
                if bounded {
                    Container::BoundedSequence(n)
                } else {
                    Container::Array(n)
                }
            };
            (&without_close[..index], container)
        } else if s.ends_with(']') {
            return Err(self.error(
                line_no,
                col,
                format!("the type '{s}' ends with ']' but has no '['"),
            ));
        } else {
            (s, Container::Single)
        };
        let base = match primitive_base(base_str) {
            Some(base) => base,
            None => {
                if let Some(bound) = base_str
                    .strip_prefix("string<=")
                    .or_else(|| base_str.strip_prefix("wstring<="))
                {
                    return Err(self.error(
                        line_no,
                        col,
                        format!("the upper bound of the string type '{base_str}' must be an integer > 0, not '{bound}'"),
                    ));
                }
                BaseType::Named(self.named_type(base_str, line_no, col)?)
            }
        };
        Ok(FieldType { base, container })
    }

    /// `pkg/Name` or `Name` (this package): a message type.
    fn named_type(&self, s: &str, line_no: usize, col: usize) -> Result<NamedType, ParseError> {
        let parts: Vec<&str> = s.split('/').collect();
        let (package, name) = match parts.as_slice() {
            [name] => (self.package, *name),
            [package, name] => (*package, *name),
            _ => {
                return Err(self.error(
                    line_no,
                    col,
                    format!(
                    "unknown type '{s}': expected a primitive type or a message type 'pkg/Name'"
                ),
                ))
            }
        };
        if !is_valid_package_name(package) {
            return Err(self.error(
                line_no,
                col,
                format!("'{package}' is not a valid package name (in type '{s}')"),
            ));
        }
        if !is_valid_message_name(name) {
            return Err(self.error(
                line_no,
                col,
                format!(
                    "unknown type '{s}': expected a primitive type or a message name in CamelCase"
                ),
            ));
        }
        Ok(NamedType::new(package, "msg", name))
    }
}

/// The 1-based column of `needle` in `line` (its first occurrence), or 1.
fn column_of(line: &str, needle: &str) -> usize {
    line.find(needle)
        .map_or(1, |i| line[..i].chars().count() + 1)
}

/// A primitive or (bounded) string type as a `.msg` names it; `time`/`duration` are
/// builtin_interfaces' (rosidl_adapter `MSG_TYPE_TO_IDL`). `None` if it is none of these.
fn primitive_base(s: &str) -> Option<BaseType> {
    let p = match s {
        "bool" => Primitive::Bool,
        "byte" => Primitive::Byte,
        "char" => Primitive::UInt8,
        "float32" => Primitive::Float32,
        "float64" => Primitive::Float64,
        "int8" => Primitive::Int8,
        "uint8" => Primitive::UInt8,
        "int16" => Primitive::Int16,
        "uint16" => Primitive::UInt16,
        "int32" => Primitive::Int32,
        "uint32" => Primitive::UInt32,
        "int64" => Primitive::Int64,
        "uint64" => Primitive::UInt64,
        "string" => return Some(BaseType::String(None)),
        "wstring" => return Some(BaseType::WString(None)),
        "time" => {
            return Some(BaseType::Named(NamedType::new(
                "builtin_interfaces",
                "msg",
                "Time",
            )))
        }
        "duration" => {
            return Some(BaseType::Named(NamedType::new(
                "builtin_interfaces",
                "msg",
                "Duration",
            )))
        }
        _ => {
            if let Some(n) = s.strip_prefix("string<=") {
                return parse_positive(n).map(|n| BaseType::String(Some(n)));
            }
            if let Some(n) = s.strip_prefix("wstring<=") {
                return parse_positive(n).map(|n| BaseType::WString(Some(n)));
            }
            return None;
        }
    };
    Some(BaseType::Primitive(p))
}

/// Python `int(s)` of a positive integer.
fn parse_positive(s: &str) -> Option<u64> {
    let n = python_int(s)?;
    u64::try_from(n).ok().filter(|&n| n > 0)
}

/// Python `int(s)` then `int(s, 0)` (rosidl_adapter's integer parsing): decimal with optional
/// sign, surrounding spaces and `_` between digits; or `0x`/`0o`/`0b` prefixed.
fn python_int(s: &str) -> Option<i128> {
    let t = s.trim();
    let (neg, body) = match t.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let (radix, digits) = match body.get(..2).map(str::to_ascii_lowercase).as_deref() {
        Some("0x") => (16, &body[2..]),
        Some("0o") => (8, &body[2..]),
        Some("0b") => (2, &body[2..]),
        _ => (10, body),
    };
    if digits.is_empty()
        || digits.starts_with('_')
        || digits.ends_with('_')
        || digits.contains("__")
        || (radix != 10 && digits.starts_with('_'))
    {
        return None;
    }
    let clean: String = digits.chars().filter(|&c| c != '_').collect();
    if !clean.chars().all(|c| c.is_digit(radix)) {
        return None;
    }
    let v = i128::from_str_radix(&clean, radix).ok()?;
    Some(if neg { -v } else { v })
}

/// rosidl_adapter `parse_value_string`: a field's default value.
fn parse_value(ty: &FieldType, s: &str) -> Result<Value, String> {
    let base = &ty.base;
    if let BaseType::Named(_) = base {
        return Err(format!(
            "a default value of the non-primitive type '{}' is not supported",
            type_string(ty)
        ));
    }
    if ty.container == Container::Single {
        return parse_primitive_value(base, s).map(Value::Scalar);
    }
    let Some(inner) = s.strip_prefix('[').and_then(|t| t.strip_suffix(']')) else {
        return Err(format!(
            "value '{s}' can not be converted to type '{}': array value must start with '[' and end with ']'",
            type_string(ty)
        ));
    };
    let elements: Vec<String> = if matches!(base, BaseType::String(_) | BaseType::WString(_)) {
        string_array_elements(inner)?
    } else if inner.is_empty() {
        Vec::new()
    } else {
        inner.split(',').map(str::to_owned).collect()
    };
    match ty.container {
        Container::Array(n) if elements.len() as u64 != n => {
            return Err(format!(
                "value '{s}' can not be converted to type '{}': array must have exactly {n} elements, not {}",
                type_string(ty),
                elements.len()
            ))
        }
        Container::BoundedSequence(n) if elements.len() as u64 > n => {
            return Err(format!(
                "value '{s}' can not be converted to type '{}': array must have not more than {n} elements, not {}",
                type_string(ty),
                elements.len()
            ))
        }
        _ => {}
    }
    elements
        .iter()
        .enumerate()
        .map(|(i, e)| {
            parse_primitive_value(base, e.trim()).map_err(|err| {
                format!(
                    "value '{s}' can not be converted to type '{}': element {i} with {err}",
                    type_string(ty)
                )
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Value::Array)
}

/// rosidl_adapter `parse_string_array_value_string`: the elements of `[...]` of a string array,
/// each quoted (`'…'`/`"…"`, the quote escaped inside) or bare up to the next comma.
fn string_array_elements(inner: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut rest = inner;
    while !rest.is_empty() {
        rest = rest.trim_start_matches(' ');
        if rest.starts_with(',') {
            return Err(format!("unexpected ',' at the beginning of [{rest}]"));
        }
        if rest.is_empty() {
            break;
        }
        let quote = rest.chars().next().filter(|&c| c == '"' || c == '\'');
        if let Some(q) = quote {
            let end = find_end_quote(rest, q)
                .ok_or_else(|| format!("string [{rest}] incorrectly quoted"))?;
            let value = &rest[1..end];
            out.push(value.replace(&format!("\\{q}"), &q.to_string()));
            rest = &rest[end + 1..];
        } else {
            match rest.find(',') {
                Some(c) => {
                    out.push(rest[..c].to_owned());
                    rest = &rest[c..];
                }
                None => {
                    out.push(rest.to_owned());
                    rest = "";
                }
            }
        }
        rest = rest.trim_start_matches(' ');
        if let Some(r) = rest.strip_prefix(',') {
            rest = r;
        } else if !rest.is_empty() {
            return Err(format!(
                "expected ',' between string elements before [{rest}]"
            ));
        }
    }
    Ok(out)
}

/// The index of the quote ending the string that starts at `s[0]`, skipping `\q`.
fn find_end_quote(s: &str, q: char) -> Option<usize> {
    let bytes = s.as_bytes();
    let mut i = 1;
    while i < bytes.len() {
        if bytes[i] == b'\\' && bytes.get(i + 1) == Some(&(q as u8)) {
            i += 2;
            continue;
        }
        if bytes[i] == q as u8 {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// rosidl_adapter `parse_primitive_value_string`.
fn parse_primitive_value(base: &BaseType, s: &str) -> Result<Literal, String> {
    let invalid =
        |what: &str, why: &str| format!("value '{s}' can not be converted to type '{what}': {why}");
    match base {
        BaseType::Primitive(Primitive::Bool) => match s.to_ascii_lowercase().as_str() {
            "true" | "1" => Ok(Literal::Bool(true)),
            "false" | "0" => Ok(Literal::Bool(false)),
            _ => Err(invalid(
                "bool",
                "must be either 'true' / '1' or 'false' / '0'",
            )),
        },
        BaseType::Primitive(
            p @ (Primitive::Float32 | Primitive::Float64 | Primitive::LongDouble),
        ) => python_float(s).map(Literal::Float).ok_or_else(|| {
            invalid(
                p.msg_name(),
                "must be a floating point number using '.' as the separator",
            )
        }),
        BaseType::Primitive(p) => {
            let (bits, signed) = p.integer().unwrap_or((8, false));
            let (lo, hi) = if signed {
                (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
            } else {
                (0, (1i128 << bits) - 1)
            };
            let name = match p {
                // `.msg` `char` is `uint8` in the model; rosidl_adapter names it as written.
                Primitive::Byte => "byte",
                other => other.msg_name(),
            };
            match python_int(s) {
                Some(v) if (lo..=hi).contains(&v) => Ok(Literal::Int(v)),
                _ => Err(invalid(
                    name,
                    &format!("must be a valid integer value >= {lo} and <= {hi}"),
                )),
            }
        }
        BaseType::String(bound) | BaseType::WString(bound) => {
            let mut v = s.to_owned();
            for q in ['"', '\''] {
                if v.len() >= 2 && v.starts_with(q) && v.ends_with(q) {
                    let inner = &v[1..v.len() - 1];
                    // An unescaped quote inside is an error (rosidl: `(?<!\\)q`).
                    let mut prev = '\0';
                    for c in inner.chars() {
                        if c == q && prev != '\\' {
                            return Err(invalid(
                                "string",
                                "string inner quotes not properly escaped",
                            ));
                        }
                        prev = c;
                    }
                    v = inner.replace(&format!("\\{q}"), &q.to_string());
                    break;
                }
            }
            if let Some(n) = bound {
                // Python `len(str)`: characters.
                if v.chars().count() as u64 > *n {
                    return Err(invalid(
                        "string",
                        &format!("string must not exceed the maximum length of {n} characters"),
                    ));
                }
            }
            Ok(Literal::String(v))
        }
        BaseType::Named(t) => Err(invalid(&t.to_string(), "not a primitive type")),
    }
}

/// Python `float(s)`: decimal or exponent notation, `inf`/`infinity`/`nan` in any case, with
/// optional sign, surrounding spaces and `_` between digits.
pub(crate) fn python_float(s: &str) -> Option<f64> {
    let t = s.trim();
    let lower = t.to_ascii_lowercase();
    let unsigned = lower.trim_start_matches(['+', '-']);
    if lower.len() - unsigned.len() > 1 {
        return None;
    }
    let negative = lower.starts_with('-');
    match unsigned {
        "inf" | "infinity" => {
            return Some(if negative {
                f64::NEG_INFINITY
            } else {
                f64::INFINITY
            })
        }
        "nan" => return Some(f64::NAN),
        _ => {}
    }
    if t.contains("__") || t.starts_with('_') || t.ends_with('_') {
        return None;
    }
    let clean: String = t.chars().filter(|&c| c != '_').collect();
    if !clean
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'))
        || !clean.chars().any(|c| c.is_ascii_digit())
    {
        return None;
    }
    clean.parse::<f64>().ok()
}

/// The `.msg` spelling of a field type (for messages).
pub fn type_string(ty: &FieldType) -> String {
    let base = match &ty.base {
        BaseType::Primitive(p) => p.msg_name().to_owned(),
        BaseType::String(None) => "string".to_owned(),
        BaseType::String(Some(n)) => format!("string<={n}"),
        BaseType::WString(None) => "wstring".to_owned(),
        BaseType::WString(Some(n)) => format!("wstring<={n}"),
        BaseType::Named(t) => format!("{}/{}", t.package, t.name),
    };
    match ty.container {
        Container::Single => base,
        Container::Array(n) => format!("{base}[{n}]"),
        Container::UnboundedSequence => format!("{base}[]"),
        Container::BoundedSequence(n) => format!("{base}[<={n}]"),
    }
}

/// rosidl_adapter `process_comments`: a `[unit]` found once becomes the unit and leaves the
/// text; leading, trailing and repeated empty lines go; the lines are dedented together
/// (Python `textwrap.dedent`).
fn process_comment(mut lines: Vec<String>) -> (Vec<String>, Option<String>) {
    let mut unit = None;
    let joined = lines.join("\n");
    let units = find_units(&joined);
    if units.len() == 1 {
        let (whole, name) = &units[0];
        unit = Some(name.clone());
        for l in &mut lines {
            *l = l.replace(whole.as_str(), "");
        }
    }
    while lines.first().is_some_and(String::is_empty) {
        lines.remove(0);
    }
    while lines.last().is_some_and(String::is_empty) {
        lines.pop();
    }
    lines.dedup_by(|b, a| a.is_empty() && b.is_empty());
    if lines.is_empty() {
        return (lines, unit);
    }
    (dedent(&lines), unit)
}

/// Matches of the regex `(\s*\[([^,\]]+)\])`: (whole match, unit).
fn find_units(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut i = 0;
    while i < chars.len() {
        // The leftmost match: whitespace run then '[' unit ']'.
        let start = i;
        let mut j = i;
        while j < chars.len() && chars[j].1.is_whitespace() {
            j += 1;
        }
        if j < chars.len() && chars[j].1 == '[' {
            let mut k = j + 1;
            while k < chars.len() && chars[k].1 != ',' && chars[k].1 != ']' {
                k += 1;
            }
            if k > j + 1 && k < chars.len() && chars[k].1 == ']' {
                let byte = |n: usize| chars.get(n).map_or(text.len(), |c| c.0);
                out.push((
                    text[byte(start)..byte(k + 1)].to_owned(),
                    text[byte(j + 1)..byte(k)].to_owned(),
                ));
                i = k + 1;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// Python `textwrap.dedent` of lines: the common leading whitespace of the non-blank lines is
/// removed; blank lines become empty.
fn dedent(lines: &[String]) -> Vec<String> {
    let margin = lines
        .iter()
        .filter(|l| !l.trim().is_empty())
        .map(|l| &l[..l.len() - l.trim_start_matches([' ', '\t']).len()])
        .reduce(|a, b| {
            let common = a
                .char_indices()
                .zip(b.chars())
                .find(|((_, x), y)| x != y)
                .map_or(a.len().min(b.len()), |((i, _), _)| i);
            &a[..common]
        })
        .unwrap_or("")
        .to_owned();
    lines
        .iter()
        .map(|l| {
            if l.trim().is_empty() {
                String::new()
            } else {
                l.strip_prefix(margin.as_str()).unwrap_or(l).to_owned()
            }
        })
        .collect()
}

/// rosidl_adapter `VALID_PACKAGE_NAME_PATTERN`: `[a-z][a-z0-9_]*`, no `__`, no trailing `_`.
pub fn is_valid_package_name(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        && !s.contains("__")
        && !s.ends_with('_')
}

/// rosidl_adapter `VALID_FIELD_NAME_PATTERN` (the package pattern).
pub fn is_valid_field_name(s: &str) -> bool {
    is_valid_package_name(s)
}

/// rosidl_adapter `VALID_MESSAGE_NAME_PATTERN`: `[A-Z][A-Za-z0-9]*`.
pub fn is_valid_message_name(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_uppercase()) && chars.all(|c| c.is_ascii_alphanumeric())
}

/// rosidl_adapter `VALID_CONSTANT_NAME_PATTERN`: `[A-Z]([A-Z0-9_]?[A-Z0-9]+)*`.
pub fn is_valid_constant_name(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_uppercase())
        && s.chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
        && !s.contains("__")
        && !s.ends_with('_')
}
