//! Plain CDR (XCDR1) bodies of dynamic values, as rmw_fastrtps_cpp and rmw_cyclonedds_cpp write
//! them: primitives aligned to their size relative to the body start, `bool`/`byte`/`char` one
//! byte, strings as `uint32` length (with the NUL) + bytes + NUL, sequences as `uint32` count +
//! elements, arrays as their elements, nested structs inline. `wchar` / `wstring` follow
//! rmw_cyclonedds (16-bit units; `wstring` length in units, no terminator).

use super::{Container, Elem, Member, Schema, SchemaError, Value, MAX_NESTING};

/// Why a value does not encode as a type ([`encode`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EncodeError {
    /// The type (or a type it uses) is not in the schema.
    #[error(transparent)]
    Schema(#[from] SchemaError),
    /// The value nests structs deeper than [`Schema::check`] allows (a type not checked).
    #[error("type '{type_name}' nests structs more than {} deep", MAX_NESTING)]
    TooDeep {
        /// The struct found too deep.
        type_name: String,
    },
    /// A struct type's value is not a [`Value::Struct`].
    #[error("value does not fit its field type ({type_name})")]
    NotAStruct {
        /// The struct type.
        type_name: String,
    },
    /// A struct value with another number of fields than its type.
    #[error("value does not fit its field type ({type_name})")]
    FieldCount {
        /// The struct type.
        type_name: String,
        /// The type's number of fields.
        expected: usize,
        /// The value's.
        found: usize,
    },
    /// An array or sequence field's value is not a [`Value::List`].
    #[error("value does not fit its field type ({field})")]
    NotAList {
        /// The field's name.
        field: String,
    },
    /// An array of another length than its type's, or a sequence longer than its bound (or
    /// than a CDR count can say).
    #[error("value does not fit its field type ({field})")]
    Length {
        /// The field's name.
        field: String,
        /// The field's container (the expected length or bound).
        container: Container,
        /// The value's length.
        found: usize,
    },
    /// A value of another kind than its element type.
    #[error("value does not fit its field type ({expected:?})")]
    WrongType {
        /// The element type.
        expected: Elem,
        /// The kind of value found (`Bool`, `Int`, `Str`…).
        found: &'static str,
    },
    /// A `char` value beyond 8 bits.
    #[error("value does not fit its field type (char)")]
    CharOutOfRange {
        /// The character.
        value: char,
    },
    /// An integer beyond its field's range.
    #[error("value does not fit its field type (integer out of range)")]
    IntegerOutOfRange {
        /// The integer.
        value: i128,
        /// The field's bits.
        bits: u32,
        /// Whether the field is signed.
        signed: bool,
    },
    /// A `string` holding a NUL, which CDR strings cannot carry.
    #[error("value does not fit its field type (string with a NUL)")]
    NulInString,
    /// A `string` longer than a CDR length can say.
    #[error("value does not fit its field type (string)")]
    StringTooLong {
        /// Its length in bytes.
        len: usize,
    },
    /// A `wstring` longer than a CDR length can say.
    #[error("value does not fit its field type (wstring)")]
    WStringTooLong {
        /// Its length in UTF-16 units.
        len: usize,
    },
    /// A `long double` field (no ROS interface uses one).
    #[error("long double fields are not supported")]
    LongDouble,
}

/// Why a body does not decode as a type ([`decode`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum DecodeError {
    /// The type (or a type it uses) is not in the schema.
    #[error(transparent)]
    Schema(#[from] SchemaError),
    /// The type nests structs deeper than [`Schema::check`] allows (a type not checked).
    #[error("type '{type_name}' nests structs more than {} deep", MAX_NESTING)]
    TooDeep {
        /// The struct found too deep.
        type_name: String,
    },
    /// The body ends before the value does.
    #[error("reply body truncated at byte {offset}")]
    Truncated {
        /// Where the next value was to be read (from the body start).
        offset: usize,
    },
    /// A sequence count beyond the field's bound or the bytes left.
    #[error("field '{field}': sequence of {len} elements")]
    SequenceTooLong {
        /// The field's name.
        field: String,
        /// The count read.
        len: usize,
        /// The field's bound, if any.
        bound: Option<usize>,
    },
    /// A `long double` field (no ROS interface uses one).
    #[error("long double fields are not supported")]
    LongDouble,
}

/// Encodes a struct value of type `type_name` as a little-endian body (`type_name` having passed
/// [`Schema::check`]).
pub fn encode(schema: &Schema, type_name: &str, value: &Value) -> Result<Vec<u8>, EncodeError> {
    let mut w = Writer {
        out: Vec::new(),
        depth: 0,
    };
    w.strukt(schema, type_name, value)?;
    Ok(w.out)
}

/// Decodes a body (in either byte order) as a struct of type `type_name` (which has passed
/// [`Schema::check`]: no element then takes 0 bytes, so a count is checked against the bytes
/// left before anything is decoded). Trailing bytes (padding) are ignored.
pub fn decode(
    schema: &Schema,
    type_name: &str,
    body: &[u8],
    big_endian: bool,
) -> Result<Value, DecodeError> {
    let mut r = Reader {
        body,
        pos: 0,
        big_endian,
        depth: 0,
    };
    r.strukt(schema, type_name)
}

/// The kind of a value, for [`EncodeError::WrongType`].
fn kind(v: &Value) -> &'static str {
    match v {
        Value::Bool(_) => "Bool",
        Value::Int(_) => "Int",
        Value::Float(_) => "Float",
        Value::Str(_) => "Str",
        Value::Byte(_) => "Byte",
        Value::List(_) => "List",
        Value::Struct(_) => "Struct",
    }
}

struct Writer {
    out: Vec<u8>,
    /// Structs being written around the current one.
    depth: usize,
}

impl Writer {
    fn align(&mut self, n: usize) {
        while !self.out.len().is_multiple_of(n) {
            self.out.push(0);
        }
    }

    fn put(&mut self, bytes: &[u8]) {
        self.align(bytes.len().min(8));
        self.out.extend_from_slice(bytes);
    }

    fn strukt(&mut self, schema: &Schema, name: &str, v: &Value) -> Result<(), EncodeError> {
        if self.depth >= MAX_NESTING {
            return Err(EncodeError::TooDeep {
                type_name: name.to_owned(),
            });
        }
        self.depth += 1;
        let result = self.fields(schema, name, v);
        self.depth -= 1;
        result
    }

    fn fields(&mut self, schema: &Schema, name: &str, v: &Value) -> Result<(), EncodeError> {
        let s = schema.get(name)?;
        let Value::Struct(fields) = v else {
            return Err(EncodeError::NotAStruct {
                type_name: name.to_owned(),
            });
        };
        if fields.len() != s.members.len() {
            return Err(EncodeError::FieldCount {
                type_name: name.to_owned(),
                expected: s.members.len(),
                found: fields.len(),
            });
        }
        for (m, f) in s.members.iter().zip(fields) {
            match m.ty.container {
                Container::Single => self.elem(schema, &m.ty.elem, f)?,
                Container::Array(n) => {
                    let Value::List(items) = f else {
                        return Err(not_a_list(m));
                    };
                    if items.len() != n {
                        return Err(wrong_length(m, items));
                    }
                    for i in items {
                        self.elem(schema, &m.ty.elem, i)?;
                    }
                }
                Container::Sequence(bound) => {
                    let Value::List(items) = f else {
                        return Err(not_a_list(m));
                    };
                    if bound.is_some_and(|b| items.len() > b) {
                        return Err(wrong_length(m, items));
                    }
                    let n = u32::try_from(items.len()).map_err(|_| wrong_length(m, items))?;
                    self.put(&n.to_le_bytes());
                    for i in items {
                        self.elem(schema, &m.ty.elem, i)?;
                    }
                }
            }
        }
        Ok(())
    }

    fn elem(&mut self, schema: &Schema, e: &Elem, v: &Value) -> Result<(), EncodeError> {
        match (e, v) {
            (Elem::Nested(n), v) => self.strukt(schema, n, v)?,
            (Elem::Bool, Value::Bool(b)) => self.out.push(u8::from(*b)),
            (Elem::Byte, Value::Byte(b)) => self.out.push(*b),
            (Elem::Char, Value::Str(s)) => {
                let c = s.chars().next().unwrap_or('\0');
                let b = u8::try_from(c).map_err(|_| EncodeError::CharOutOfRange { value: c })?;
                self.out.push(b);
            }
            (Elem::WChar, Value::Str(s)) => {
                let c = s.encode_utf16().next().unwrap_or(0);
                self.put(&c.to_le_bytes());
            }
            (Elem::Int { bits, signed }, Value::Int(i)) => {
                let bytes = (*i).to_le_bytes();
                let n = (*bits / 8) as usize;
                let (lo, hi) = if *signed {
                    (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
                } else {
                    (0, (1i128 << bits) - 1)
                };
                if *i < lo || *i > hi {
                    return Err(EncodeError::IntegerOutOfRange {
                        value: *i,
                        bits: *bits,
                        signed: *signed,
                    });
                }
                self.put(&bytes[..n]);
            }
            (Elem::F32, Value::Float(f)) => self.put(&(*f as f32).to_le_bytes()),
            (Elem::F64, Value::Float(f)) => self.put(&f.to_le_bytes()),
            (Elem::LongDouble, _) => return Err(EncodeError::LongDouble),
            (Elem::Str(_), Value::Str(s)) => {
                if s.contains('\0') {
                    return Err(EncodeError::NulInString);
                }
                let n = u32::try_from(s.len() + 1)
                    .map_err(|_| EncodeError::StringTooLong { len: s.len() })?;
                self.put(&n.to_le_bytes());
                self.out.extend_from_slice(s.as_bytes());
                self.out.push(0);
            }
            // rosidl_typesupport_fastrtps `serialization_helpers.hpp` (and rmw_cyclonedds'
            // `CDR_Legacy`): the count of UTF-16 units, then each unit as a 4-byte integer.
            (Elem::WStr(_), Value::Str(s)) => {
                let units: Vec<u16> = s.encode_utf16().collect();
                let n = u32::try_from(units.len())
                    .map_err(|_| EncodeError::WStringTooLong { len: units.len() })?;
                self.put(&n.to_le_bytes());
                for u in units {
                    self.out.extend_from_slice(&u32::from(u).to_le_bytes());
                }
            }
            (e, v) => {
                return Err(EncodeError::WrongType {
                    expected: e.clone(),
                    found: kind(v),
                })
            }
        }
        Ok(())
    }
}

/// An [`EncodeError::NotAList`] for field `m`.
fn not_a_list(m: &Member) -> EncodeError {
    EncodeError::NotAList {
        field: m.name.clone(),
    }
}

/// An [`EncodeError::Length`] for field `m` holding `items`.
fn wrong_length(m: &Member, items: &[Value]) -> EncodeError {
    EncodeError::Length {
        field: m.name.clone(),
        container: m.ty.container,
        found: items.len(),
    }
}

struct Reader<'a> {
    body: &'a [u8],
    pos: usize,
    big_endian: bool,
    /// Structs being read around the current one.
    depth: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], DecodeError> {
        let align = N.min(8);
        let start = self.pos.div_ceil(align) * align;
        let end = start + N;
        let bytes = self
            .body
            .get(start..end)
            .ok_or(DecodeError::Truncated { offset: start })?;
        self.pos = end;
        let mut out = [0u8; N];
        out.copy_from_slice(bytes);
        if self.big_endian {
            out.reverse();
        }
        Ok(out)
    }

    fn u32(&mut self) -> Result<u32, DecodeError> {
        Ok(u32::from_le_bytes(self.take::<4>()?))
    }

    fn raw(&mut self, n: usize) -> Result<&[u8], DecodeError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|e| *e <= self.body.len())
            .ok_or(DecodeError::Truncated { offset: self.pos })?;
        let s = &self.body[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    /// Bytes not read yet.
    fn left(&self) -> usize {
        self.body.len().saturating_sub(self.pos)
    }

    fn strukt(&mut self, schema: &Schema, name: &str) -> Result<Value, DecodeError> {
        if self.depth >= MAX_NESTING {
            return Err(DecodeError::TooDeep {
                type_name: name.to_owned(),
            });
        }
        self.depth += 1;
        let result = self.fields(schema, name);
        self.depth -= 1;
        result
    }

    fn fields(&mut self, schema: &Schema, name: &str) -> Result<Value, DecodeError> {
        let s = schema.get(name)?;
        let mut fields = Vec::with_capacity(s.members.len());
        for m in &s.members {
            let v = match m.ty.container {
                Container::Single => self.elem(schema, &m.ty.elem)?,
                Container::Array(n) => {
                    // Every element takes at least one byte (checked types).
                    if n > self.left() {
                        return Err(DecodeError::Truncated { offset: self.pos });
                    }
                    Value::List(
                        (0..n)
                            .map(|_| self.elem(schema, &m.ty.elem))
                            .collect::<Result<_, _>>()?,
                    )
                }
                Container::Sequence(bound) => {
                    let n = self.u32()? as usize;
                    if bound.is_some_and(|b| n > b) || n > self.left() {
                        return Err(DecodeError::SequenceTooLong {
                            field: m.name.clone(),
                            len: n,
                            bound,
                        });
                    }
                    Value::List(
                        (0..n)
                            .map(|_| self.elem(schema, &m.ty.elem))
                            .collect::<Result<_, _>>()?,
                    )
                }
            };
            fields.push(v);
        }
        Ok(Value::Struct(fields))
    }

    fn elem(&mut self, schema: &Schema, e: &Elem) -> Result<Value, DecodeError> {
        Ok(match e {
            Elem::Nested(n) => self.strukt(schema, n)?,
            Elem::Bool => Value::Bool(self.take::<1>()?[0] != 0),
            Elem::Byte => Value::Byte(self.take::<1>()?[0]),
            Elem::Char => Value::Str(char::from(self.take::<1>()?[0]).to_string()),
            Elem::WChar => {
                let u = u16::from_le_bytes(self.take::<2>()?);
                Value::Str(String::from_utf16_lossy(&[u]))
            }
            Elem::Int { bits, signed } => {
                let i: i128 = match (bits, signed) {
                    (8, true) => i128::from(i8::from_le_bytes(self.take::<1>()?)),
                    (8, false) => i128::from(self.take::<1>()?[0]),
                    (16, true) => i128::from(i16::from_le_bytes(self.take::<2>()?)),
                    (16, false) => i128::from(u16::from_le_bytes(self.take::<2>()?)),
                    (32, true) => i128::from(i32::from_le_bytes(self.take::<4>()?)),
                    (32, false) => i128::from(u32::from_le_bytes(self.take::<4>()?)),
                    (64, true) => i128::from(i64::from_le_bytes(self.take::<8>()?)),
                    _ => i128::from(u64::from_le_bytes(self.take::<8>()?)),
                };
                Value::Int(i)
            }
            Elem::F32 => Value::Float(f64::from(f32::from_le_bytes(self.take::<4>()?))),
            Elem::F64 => Value::Float(f64::from_le_bytes(self.take::<8>()?)),
            Elem::LongDouble => return Err(DecodeError::LongDouble),
            Elem::Str(_) => {
                let n = self.u32()? as usize;
                let bytes = self.raw(n)?;
                let bytes = bytes.strip_suffix(&[0]).unwrap_or(bytes);
                Value::Str(String::from_utf8_lossy(bytes).into_owned())
            }
            Elem::WStr(_) => {
                let n = self.u32()? as usize;
                if n > self.left() / 4 {
                    return Err(DecodeError::Truncated { offset: self.pos });
                }
                // 4 bytes per UTF-16 unit (see the encoder); a value past 16 bits is no unit.
                let units = (0..n)
                    .map(|_| {
                        self.take::<4>()
                            .map(|b| u16::try_from(u32::from_le_bytes(b)).unwrap_or(0xfffd))
                    })
                    .collect::<Result<Vec<u16>, _>>()?;
                Value::Str(String::from_utf16_lossy(&units))
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::yaml::fill_from_yaml;
    use super::*;
    use horus_ros_msgs::cdr::{from_cdr_body, to_cdr_body};
    use horus_ros_msgs::example_interfaces::srv::{AddTwoInts, AddTwoIntsRequest};
    use horus_ros_msgs::rcl_interfaces::msg::{Parameter, ParameterValue};
    use horus_ros_msgs::rcl_interfaces::srv::{SetParameters, SetParametersRequest};
    use horus_ros_msgs::std_srvs::srv::{SetBool, SetBoolRequest, SetBoolResponse};
    use horus_ros_msgs::type_description_interfaces::srv::{
        GetTypeDescription, GetTypeDescriptionResponse,
    };
    use horus_ros_msgs::{Byte, Message, Service};

    fn schema_of<S: Service>() -> Schema {
        Schema::from_description(&S::type_description()).expect("schema")
    }

    #[test]
    fn add_two_ints_encodes_like_serde() {
        let schema = schema_of::<AddTwoInts>();
        let v =
            fill_from_yaml(&schema, AddTwoIntsRequest::TYPE_NAME, "{a: 2, b: -3}").expect("fill");
        let ours = encode(&schema, AddTwoIntsRequest::TYPE_NAME, &v).expect("encode");
        let serde = to_cdr_body(&AddTwoIntsRequest { a: 2, b: -3 }).expect("serde");
        assert_eq!(ours, serde);
        assert_eq!(
            decode(&schema, AddTwoIntsRequest::TYPE_NAME, &ours, false).expect("decode"),
            v
        );
    }

    #[test]
    fn set_bool_encodes_like_serde_and_decodes_its_response() {
        let schema = schema_of::<SetBool>();
        let v = fill_from_yaml(&schema, SetBoolRequest::TYPE_NAME, "data: true").expect("fill");
        let ours = encode(&schema, SetBoolRequest::TYPE_NAME, &v).expect("encode");
        assert_eq!(
            ours,
            to_cdr_body(&SetBoolRequest { data: true }).expect("serde")
        );
        let resp = to_cdr_body(&SetBoolResponse {
            success: true,
            message: "héllo".into(),
        })
        .expect("serde");
        let d = decode(&schema, SetBoolResponse::TYPE_NAME, &resp, false).expect("decode");
        assert_eq!(
            d,
            Value::Struct(vec![Value::Bool(true), Value::Str("héllo".into())])
        );
        let round = encode(&schema, SetBoolResponse::TYPE_NAME, &d).expect("encode");
        assert_eq!(round, resp);
    }

    #[test]
    fn set_parameters_with_nested_sequences_and_strings_encodes_like_serde() {
        let schema = schema_of::<SetParameters>();
        let yaml = "parameters:\n  - name: a\n    value: {type: 2, integer_value: 7}\n  - name: \
                    bcd\n    value:\n      type: 9\n      byte_array_value: [1, 255]\n      \
                    double_array_value: [1.5, -2]\n      string_array_value: ['x', yz]\n      \
                    bool_array_value: [true, false, true]\n";
        let v = fill_from_yaml(&schema, SetParametersRequest::TYPE_NAME, yaml).expect("fill");
        let typed = SetParametersRequest {
            parameters: vec![
                Parameter {
                    name: "a".into(),
                    value: ParameterValue {
                        r#type: 2,
                        integer_value: 7,
                        ..Default::default()
                    },
                },
                Parameter {
                    name: "bcd".into(),
                    value: ParameterValue {
                        r#type: 9,
                        byte_array_value: vec![Byte(1), Byte(255)],
                        double_array_value: vec![1.5, -2.0],
                        string_array_value: vec!["x".into(), "yz".into()],
                        bool_array_value: vec![true, false, true],
                        ..Default::default()
                    },
                },
            ],
        };
        let ours = encode(&schema, SetParametersRequest::TYPE_NAME, &v).expect("encode");
        assert_eq!(ours, to_cdr_body(&typed).expect("serde"));
        let back: SetParametersRequest =
            from_cdr_body::<_, byteorder::LittleEndian>(&ours).expect("serde decode");
        assert_eq!(back, typed);
        assert_eq!(
            decode(&schema, SetParametersRequest::TYPE_NAME, &ours, false).expect("decode"),
            v
        );
    }

    #[test]
    fn type_description_responses_round_trip() {
        // Bounded strings, u64 after u8, sequences of nested structs holding sequences.
        let schema = schema_of::<GetTypeDescription>();
        let typed = GetTypeDescriptionResponse {
            successful: true,
            failure_reason: String::new(),
            type_description: SetParameters::type_description(),
            type_sources: Vec::new(),
            extra_information: Vec::new(),
        };
        let body = to_cdr_body(&typed).expect("serde");
        let v =
            decode(&schema, GetTypeDescriptionResponse::TYPE_NAME, &body, false).expect("decode");
        let again = encode(&schema, GetTypeDescriptionResponse::TYPE_NAME, &v).expect("encode");
        assert_eq!(again, body);
    }

    #[test]
    fn big_endian_bodies_decode() {
        let schema = schema_of::<AddTwoInts>();
        let mut body = Vec::new();
        body.extend_from_slice(&5i64.to_be_bytes());
        body.extend_from_slice(&(-1i64).to_be_bytes());
        let v = decode(&schema, AddTwoIntsRequest::TYPE_NAME, &body, true).expect("decode");
        assert_eq!(v, Value::Struct(vec![Value::Int(5), Value::Int(-1)]));
    }

    #[test]
    fn truncated_bodies_are_errors() {
        let schema = schema_of::<AddTwoInts>();
        assert!(decode(&schema, AddTwoIntsRequest::TYPE_NAME, &[0; 12], false).is_err());
    }
}
