//! Python's `repr()` of a message as rclpy prints it (rosidl_generator_py jazzy `_msg.py.em`
//! `__repr__`): `pkg.srv.Name_Request(a=2, b=3)`; strings as Python `repr(str)`; numeric
//! sequences (stored as `array.array`) as plain lists `[1, 2]`; numeric fixed arrays as numpy's
//! `repr` (`array([1., 2.])`, `array([1, 2], dtype=int32)`; numpy 1.26 defaults: precision 8,
//! line width 75); `bytes` as `b'\x01'`; other arrays and sequences as Python lists.

use super::{Container, Elem, Schema, Value};

/// The repr of a struct value of type `type_name`.
pub fn repr(schema: &Schema, type_name: &str, value: &Value) -> String {
    let mut out = String::new();
    strukt(schema, type_name, value, &mut out);
    out
}

fn strukt(schema: &Schema, name: &str, v: &Value, out: &mut String) {
    out.push_str(&name.replace('/', "."));
    out.push('(');
    let (Ok(s), Value::Struct(fields)) = (schema.get(name), v) else {
        out.push_str("...)");
        return;
    };
    if !s.is_empty_placeholder() {
        for (i, (m, f)) in s.members.iter().zip(fields).enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            out.push_str(&m.name);
            out.push('=');
            match (m.ty.container, f) {
                (Container::Single, f) => elem(schema, &m.ty.elem, f, out),
                (Container::Array(_), Value::List(items)) if numeric(&m.ty.elem) => {
                    out.push_str(&numpy_repr(&m.ty.elem, items));
                }
                (_, Value::List(items)) => {
                    out.push('[');
                    for (j, item) in items.iter().enumerate() {
                        if j > 0 {
                            out.push_str(", ");
                        }
                        elem(schema, &m.ty.elem, item, out);
                    }
                    out.push(']');
                }
                (_, other) => out.push_str(&format!("{other:?}")),
            }
        }
    }
    out.push(')');
}

/// Whether rclpy stores arrays of this element in numpy / `array.array`
/// (`SPECIAL_NESTED_BASIC_TYPES`).
fn numeric(e: &Elem) -> bool {
    matches!(e, Elem::Int { .. } | Elem::F32 | Elem::F64)
}

fn elem(schema: &Schema, e: &Elem, v: &Value, out: &mut String) {
    match (e, v) {
        (Elem::Nested(n), v) => strukt(schema, n, v, out),
        (_, Value::Bool(b)) => out.push_str(if *b { "True" } else { "False" }),
        (_, Value::Int(i)) => out.push_str(&i.to_string()),
        (_, Value::Float(f)) => out.push_str(&py_float(*f)),
        (_, Value::Str(s)) => out.push_str(&py_str(s)),
        (_, Value::Byte(b)) => out.push_str(&py_bytes(&[*b])),
        (_, other) => out.push_str(&format!("{other:?}")),
    }
}

/// Python `repr(float)`: shortest round-trip digits, exponent form below 1e-4 and from 1e16 on.
pub fn py_float(f: f64) -> String {
    if f.is_nan() {
        return "nan".to_owned();
    }
    if f.is_infinite() {
        return if f > 0.0 { "inf" } else { "-inf" }.to_owned();
    }
    let (neg, digits, exp) = shortest(f);
    let sign = if neg { "-" } else { "" };
    // Python: decimal point position decpt = exp + 1; exponent form if decpt <= -4 or > 16.
    if !(-4..16).contains(&exp) {
        let mant = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits.clone()
        };
        let esign = if exp < 0 { '-' } else { '+' };
        format!("{sign}{mant}e{esign}{:02}", exp.abs())
    } else {
        format!("{sign}{}", positional(&digits, exp, true))
    }
}

/// `str()` of a numpy `float32` (numpy >= 1.14: the shortest digits that round-trip as float32,
/// laid out as Python lays out floats).
pub fn py_float32_numpy(f: f32) -> String {
    if f.is_nan() {
        return "nan".to_owned();
    }
    if f.is_infinite() {
        return if f > 0.0 { "inf" } else { "-inf" }.to_owned();
    }
    let (neg, digits, exp) = shortest32(f);
    let sign = if neg { "-" } else { "" };
    if !(-4..16).contains(&exp) {
        let mant = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits.clone()
        };
        let esign = if exp < 0 { '-' } else { '+' };
        format!("{sign}{mant}e{esign}{:02}", exp.abs())
    } else {
        format!("{sign}{}", positional(&digits, exp, true))
    }
}

/// (negative, significant digits without leading/trailing zeros, decimal exponent of the first
/// digit) of the shortest round-trip representation.
fn shortest(f: f64) -> (bool, String, i32) {
    split_exp(&format!("{:e}", f))
}

fn shortest32(f: f32) -> (bool, String, i32) {
    split_exp(&format!("{:e}", f))
}

fn split_exp(s: &str) -> (bool, String, i32) {
    let (neg, s) = match s.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, s),
    };
    let (mant, exp) = s.split_once('e').unwrap_or((s, "0"));
    let digits: String = mant.chars().filter(char::is_ascii_digit).collect();
    let digits = digits.trim_end_matches('0');
    let digits = if digits.is_empty() { "0" } else { digits };
    (neg, digits.to_owned(), exp.parse().unwrap_or(0))
}

/// Digits `d1 d2 …` × 10^(exp) (d1 at 10^exp) in positional form; `dot_zero`: Python's `1.0`
/// (else numpy's `1.`).
fn positional(digits: &str, exp: i32, dot_zero: bool) -> String {
    let (int, frac) = if exp < 0 {
        (
            "0".to_owned(),
            format!("{}{digits}", "0".repeat((-exp - 1) as usize)),
        )
    } else {
        let k = (exp + 1) as usize;
        if digits.len() > k {
            (digits[..k].to_owned(), digits[k..].to_owned())
        } else {
            (
                format!("{digits}{}", "0".repeat(k - digits.len())),
                String::new(),
            )
        }
    };
    let frac = if digits == "0" { String::new() } else { frac };
    if frac.is_empty() && dot_zero {
        format!("{int}.0")
    } else {
        format!("{int}.{frac}")
    }
}

/// Python `repr(str)`.
pub fn py_str(s: &str) -> String {
    let quote = if s.contains('\'') && !s.contains('"') {
        '"'
    } else {
        '\''
    };
    let mut out = String::with_capacity(s.len() + 2);
    out.push(quote);
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c == quote => {
                out.push('\\');
                out.push(c);
            }
            c if c.is_control() || (c.is_whitespace() && c != ' ') => {
                let n = u32::from(c);
                if n < 0x100 {
                    out.push_str(&format!("\\x{n:02x}"));
                } else if n < 0x10000 {
                    out.push_str(&format!("\\u{n:04x}"));
                } else {
                    out.push_str(&format!("\\U{n:08x}"));
                }
            }
            c => out.push(c),
        }
    }
    out.push(quote);
    out
}

/// Python `repr(bytes)`.
pub fn py_bytes(b: &[u8]) -> String {
    let quote = if b.contains(&b'\'') && !b.contains(&b'"') {
        b'"'
    } else {
        b'\''
    };
    let mut out = String::from("b");
    out.push(char::from(quote));
    for &c in b {
        match c {
            b'\\' => out.push_str("\\\\"),
            b'\n' => out.push_str("\\n"),
            b'\r' => out.push_str("\\r"),
            b'\t' => out.push_str("\\t"),
            c if c == quote => {
                out.push('\\');
                out.push(char::from(c));
            }
            0x20..=0x7e => out.push(char::from(c)),
            c => out.push_str(&format!("\\x{c:02x}")),
        }
    }
    out.push(char::from(quote));
    out
}

/// numpy's `repr` of a 1-D array of `e` (numpy 1.26, default print options).
fn numpy_repr(e: &Elem, items: &[Value]) -> String {
    let dtype = match e {
        Elem::Int {
            bits: 64,
            signed: true,
        }
        | Elem::F64 => None,
        Elem::Int { bits, signed } => Some(format!("{}int{bits}", if *signed { "" } else { "u" })),
        _ => Some("float32".to_owned()),
    };
    let words = match e {
        Elem::Int { .. } => {
            let strs: Vec<String> = items
                .iter()
                .map(|v| match v {
                    Value::Int(i) => i.to_string(),
                    other => format!("{other:?}"),
                })
                .collect();
            let w = strs.iter().map(String::len).max().unwrap_or(0);
            strs.into_iter().map(|s| format!("{s:>w$}")).collect()
        }
        _ => {
            let vals: Vec<f64> = items
                .iter()
                .map(|v| match v {
                    Value::Float(f) => *f,
                    _ => f64::NAN,
                })
                .collect();
            numpy_floats(&vals, *e == Elem::F32)
        }
    };
    const LINE_WIDTH: usize = 75;
    let prefix = "array(";
    let suffix = if dtype.is_some() { "," } else { ")" };
    let body = numpy_format_1d(&words, LINE_WIDTH - suffix.len(), prefix.len() + 1);
    let arr = format!("{prefix}{body}{suffix}");
    match dtype {
        None => arr,
        Some(d) => {
            let dtype_str = format!("dtype={d})");
            let last_line = arr.len() - arr.rfind('\n').map_or(0, |i| i + 1);
            let spacer = if last_line + dtype_str.len() + 1 > LINE_WIDTH {
                format!("\n{}", " ".repeat(prefix.len()))
            } else {
                " ".to_owned()
            };
            format!("{arr}{spacer}{dtype_str}")
        }
    }
}

/// numpy `_formatArray` for one dimension: `[a, b, …]`, wrapped at `line_width` with a hanging
/// indent of `indent` spaces.
fn numpy_format_1d(words: &[String], line_width: usize, indent: usize) -> String {
    let hanging = " ".repeat(indent);
    let elem_width = line_width - 1;
    let mut s = String::new();
    let mut line = hanging.clone();
    for (i, word) in words.iter().enumerate() {
        let needs_wrap = line.len() + word.len() > elem_width && line.len() > hanging.len();
        if needs_wrap {
            s.push_str(line.trim_end());
            s.push('\n');
            line = hanging.clone();
        }
        line.push_str(word);
        if i + 1 < words.len() {
            line.push_str(", ");
        }
    }
    s.push_str(&line);
    format!("[{}]", &s[hanging.len().min(s.len())..])
}

/// numpy `FloatingFormat` (floatmode `maxprec`, precision 8, sign `-`): every element padded to
/// a common layout.
fn numpy_floats(vals: &[f64], single: bool) -> Vec<String> {
    const PRECISION: usize = 8;
    let digits_of = |f: f64| {
        if single {
            shortest32(f as f32)
        } else {
            shortest(f)
        }
    };
    let finite: Vec<f64> = vals.iter().copied().filter(|f| f.is_finite()).collect();
    let nonzero: Vec<f64> = finite
        .iter()
        .map(|f| f.abs())
        .filter(|f| *f != 0.0)
        .collect();
    let exp_format = if nonzero.is_empty() {
        false
    } else {
        let max = nonzero.iter().copied().fold(f64::MIN, f64::max);
        let min = nonzero.iter().copied().fold(f64::MAX, f64::min);
        max >= 1e8 || min < 0.0001 || max / min > 1000.0
    };
    let (pad_left, pad_right, formatted): (usize, usize, Vec<Option<String>>) = if exp_format {
        // dragon4_scientific, unique, trimmed; then all mantissas to the longest fraction.
        let parts: Vec<Option<(bool, String, i32)>> = vals
            .iter()
            .map(|f| {
                f.is_finite()
                    .then(|| round_digits(digits_of(*f), PRECISION + 1))
            })
            .collect();
        let precision = parts
            .iter()
            .flatten()
            .map(|(_, d, _)| d.len() - 1)
            .max()
            .unwrap_or(0);
        let exp_size = parts
            .iter()
            .flatten()
            .map(|(_, _, e)| e.abs().to_string().len().max(2))
            .max()
            .unwrap_or(2);
        let strs: Vec<Option<String>> = parts
            .iter()
            .map(|p| {
                p.as_ref().map(|(neg, d, e)| {
                    let frac = format!("{:0<precision$}", &d[1..]);
                    format!(
                        "{}{}.{frac}e{}{:0>exp_size$}",
                        if *neg { "-" } else { "" },
                        &d[..1],
                        if *e < 0 { '-' } else { '+' },
                        e.abs()
                    )
                })
            })
            .collect();
        let pad_left = strs
            .iter()
            .flatten()
            .map(|s| s.find('.').unwrap_or(0))
            .max()
            .unwrap_or(0);
        (pad_left, exp_size + 2 + precision, strs)
    } else {
        let strs: Vec<Option<String>> = vals
            .iter()
            .map(|f| {
                f.is_finite().then(|| {
                    let (neg, d, e) = digits_of(*f);
                    let (d, e) = round_fraction(&d, e, PRECISION);
                    format!("{}{}", if neg { "-" } else { "" }, positional(&d, e, false))
                })
            })
            .collect();
        let pad_left = strs
            .iter()
            .flatten()
            .map(|s| s.find('.').unwrap_or(0))
            .max()
            .unwrap_or(0);
        let pad_right = strs
            .iter()
            .flatten()
            .map(|s| s.len() - s.find('.').map_or(s.len(), |i| i + 1))
            .max()
            .unwrap_or(0);
        (pad_left, pad_right, strs)
    };
    let mut pad_left = pad_left;
    if finite.len() != vals.len() {
        let neginf = vals.iter().any(|f| f.is_infinite() && *f < 0.0);
        let offset = pad_right + 1;
        pad_left = pad_left
            .max(3usize.saturating_sub(offset))
            .max((3 + usize::from(neginf)).saturating_sub(offset));
    }
    vals.iter()
        .zip(formatted)
        .map(|(f, s)| match s {
            Some(s) if !exp_format => {
                let dot = s.find('.').unwrap_or(s.len());
                let (int, frac) = s.split_at(dot);
                let frac = &frac[1.min(frac.len())..];
                format!("{int:>pad_left$}.{frac:<pad_right$}")
            }
            Some(s) => {
                let dot = s.find('.').unwrap_or(0);
                format!("{}{s}", " ".repeat(pad_left.saturating_sub(dot)))
            }
            None => {
                let word = if f.is_nan() {
                    "nan"
                } else if *f > 0.0 {
                    "inf"
                } else {
                    "-inf"
                };
                format!("{word:>w$}", w = pad_left + pad_right + 1)
            }
        })
        .collect()
}

/// Rounds significant digits to at most `n` (half up), trimming trailing zeros.
fn round_digits((neg, d, e): (bool, String, i32), n: usize) -> (bool, String, i32) {
    if d.len() <= n {
        return (neg, d, e);
    }
    let (d, carried) = round_str(&d[..n], d.as_bytes()[n] >= b'5');
    let e = if carried { e + 1 } else { e };
    let d = d.trim_end_matches('0');
    (neg, if d.is_empty() { "0".into() } else { d.into() }, e)
}

/// Keeps at most `frac` digits after the decimal point (half up).
fn round_fraction(d: &str, e: i32, frac: usize) -> (String, i32) {
    // digit i sits at 10^(e - i); keep those with e - i >= -frac.
    let keep = e + 1 + frac as i32;
    if keep >= d.len() as i32 {
        return (d.to_owned(), e);
    }
    if keep <= 0 {
        let up = keep == 0 && d.as_bytes()[0] >= b'5';
        return if up {
            ("1".to_owned(), e + 1)
        } else {
            ("0".to_owned(), 0)
        };
    }
    let k = keep as usize;
    let (r, carried) = round_str(&d[..k], d.as_bytes()[k] >= b'5');
    let r = r.trim_end_matches('0');
    let r = if r.is_empty() { "0" } else { r };
    (r.to_owned(), if carried { e + 1 } else { e })
}

/// Adds one unit in the last place if `up`; returns the digits and whether a new leading digit
/// appeared (`999` → `1000`, reported as `1` + carried).
fn round_str(d: &str, up: bool) -> (String, bool) {
    if !up {
        return (d.to_owned(), false);
    }
    let mut b = d.as_bytes().to_vec();
    for i in (0..b.len()).rev() {
        if b[i] == b'9' {
            b[i] = b'0';
        } else {
            b[i] += 1;
            return (String::from_utf8_lossy(&b).into_owned(), false);
        }
    }
    b.insert(0, b'1');
    b.pop();
    (String::from_utf8_lossy(&b).into_owned(), true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(v: &[f64]) -> String {
        numpy_repr(
            &Elem::F64,
            &v.iter().map(|x| Value::Float(*x)).collect::<Vec<_>>(),
        )
    }

    #[test]
    fn python_floats() {
        assert_eq!(py_float(1.0), "1.0");
        assert_eq!(py_float(-0.5), "-0.5");
        assert_eq!(py_float(0.1), "0.1");
        assert_eq!(py_float(1e-5), "1e-05");
        assert_eq!(py_float(0.0001), "0.0001");
        assert_eq!(py_float(1.5e16), "1.5e+16");
        assert_eq!(py_float(1e15), "1000000000000000.0");
        assert_eq!(py_float(f64::from(0.1f32)), "0.10000000149011612");
        assert_eq!(py_float(123.456), "123.456");
        assert_eq!(py_float(0.0), "0.0");
    }

    #[test]
    fn python_strings_and_bytes() {
        assert_eq!(py_str("abc"), "'abc'");
        assert_eq!(py_str("it's"), "\"it's\"");
        assert_eq!(py_str("a'\"b"), "'a\\'\"b'");
        assert_eq!(py_str("a\nb\\"), "'a\\nb\\\\'");
        assert_eq!(py_str("é\u{1}"), "'é\\x01'");
        assert_eq!(py_bytes(&[0]), "b'\\x00'");
        assert_eq!(py_bytes(b"A"), "b'A'");
        assert_eq!(py_bytes(b"'"), "b\"'\"");
    }

    #[test]
    fn numpy_arrays() {
        assert_eq!(f(&[0.0, 0.0, 0.0]), "array([0., 0., 0.])");
        assert_eq!(f(&[1.0, 2.5, 3.0]), "array([1. , 2.5, 3. ])");
        assert_eq!(f(&[-1.0, 10.25]), "array([-1.  , 10.25])");
        assert_eq!(f(&[1.0 / 3.0]), "array([0.33333333])");
        assert_eq!(f(&[1e-5, 1.0]), "array([1.e-05, 1.e+00])");
        assert_eq!(f(&[1.5e-5, 1.0]), "array([1.5e-05, 1.0e+00])");
        assert_eq!(f(&[f64::NAN, 1.0]), "array([nan,  1.])");
        let ints = |bits, signed, v: &[i128]| {
            numpy_repr(
                &Elem::Int { bits, signed },
                &v.iter().map(|x| Value::Int(*x)).collect::<Vec<_>>(),
            )
        };
        assert_eq!(ints(64, true, &[1, 2, 3]), "array([1, 2, 3])");
        assert_eq!(
            ints(32, true, &[1, -10, 100]),
            "array([  1, -10, 100], dtype=int32)"
        );
        assert_eq!(ints(8, false, &[0, 0]), "array([0, 0], dtype=uint8)");
        assert_eq!(
            numpy_repr(&Elem::F32, &[Value::Float(f64::from(0.1f32))]),
            "array([0.1], dtype=float32)"
        );
        let many: Vec<f64> = (0..30).map(f64::from).collect();
        assert_eq!(
            f(&many),
            "array([ 0.,  1.,  2.,  3.,  4.,  5.,  6.,  7.,  8.,  9., 10., 11., 12.,\n       \
             13., 14., 15., 16., 17., 18., 19., 20., 21., 22., 23., 24., 25.,\n       \
             26., 27., 28., 29.])"
        );
    }
}
