//! Dynamic ROS types: messages known only through a `type_description_interfaces`
//! [`TypeDescription`] (from a node's `~/get_type_description`, or a compiled type's own
//! description), filled from ros2cli's YAML, encoded to and decoded from CDR (XCDR1), and printed
//! as rclpy prints messages (`__repr__` of rosidl_generator_py).
//!
//! - [`Schema`]: the structs of one description, resolved by name.
//! - [`yaml`]: `rosidl_runtime_py.set_message_fields` on a YAML document.
//! - [`cdr`]: encode / decode bodies.
//! - [`repr`]: Python `repr()` of a message.
//! - [`convert`]: rosidl_runtime_py `message_to_ordereddict` / `message_to_csv`.
//! - [`pyyaml`]: PyYAML's `yaml.dump` of those values, as ros2cli prints them.
//! - [`json`]: messages as JSON objects, and filled from them.
//! - [`compiled`]: the types compiled into horus-ros-msgs, by name.
//! - [`ServiceType`]: a service type known at run time, its requests filled from YAML or JSON
//!   and its responses decoded.

pub mod cdr;
pub mod compiled;
pub mod convert;
#[doc(hidden)]
pub mod fuzzing;
pub mod json;
pub mod pyyaml;
pub mod repr;
mod service_type;
pub mod yaml;

pub use cdr::{DecodeError, EncodeError};
pub use service_type::{compiled_description, RequestError, ServiceType};
pub use yaml::FillError;

use std::collections::HashMap;

use horus_ros_msgs::description::EMPTY_STRUCTURE_MEMBER;
use horus_ros_msgs::{FieldType, IndividualTypeDescription, TypeDescription};

/// The deepest nesting of structs [`Schema::check`] accepts. rosidl sets no limit; ROS
/// interfaces nest a few levels, and rclpy, recursing per level, stops near Python's limit of
/// 1000 frames.
pub const MAX_NESTING: usize = 100;

/// The most values (fields, fixed-array elements, nested structs) outside sequences that
/// [`Schema::check`] accepts in a type: what its default value materializes before any byte is
/// read. ROS interfaces hold a few hundred at most; a description that claims more (`uint8[4e9]`)
/// is refused rather than allocated.
pub const MAX_FIXED_VALUES: u64 = 1 << 20;

/// The element type of a field (what a single value, array element or sequence element is).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Elem {
    /// `bool`.
    Bool,
    /// `byte` (IDL `octet`): a Python `bytes` of length 1.
    Byte,
    /// IDL `char`: a Python `str` of length 1.
    Char,
    /// IDL `wchar` (16 bits on the wire).
    WChar,
    /// An integer: bits and signedness.
    Int {
        /// 8, 16, 32 or 64.
        bits: u32,
        /// Signed?
        signed: bool,
    },
    /// `float32`.
    F32,
    /// `float64`.
    F64,
    /// `long double` (not encodable: no ROS interface uses it).
    LongDouble,
    /// `string` / `string<=N`.
    Str(Option<u64>),
    /// `wstring` / `wstring<=N`.
    WStr(Option<u64>),
    /// A nested message, by type name.
    Nested(String),
}

/// Single value, fixed array or sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Container {
    /// One value.
    Single,
    /// `T[N]`.
    Array(usize),
    /// `T[]` (`None`) or `T[<=N]`.
    Sequence(Option<usize>),
}

/// A field's type.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldTy {
    /// The element.
    pub elem: Elem,
    /// The container.
    pub container: Container,
}

/// One field of a struct.
#[derive(Clone, Debug)]
pub struct Member {
    /// Field name.
    pub name: String,
    /// Field type.
    pub ty: FieldTy,
    /// The `.msg` default as rosidl writes it into descriptions (empty if none).
    pub default: String,
}

/// A struct type.
#[derive(Clone, Debug)]
pub struct Struct {
    /// `pkg/msg/Name`.
    pub name: String,
    /// Fields in order.
    pub members: Vec<Member>,
}

impl Struct {
    /// Whether this is rosidl's placeholder-only empty struct (Python hides the member).
    pub fn is_empty_placeholder(&self) -> bool {
        self.members.len() == 1 && self.members[0].name == EMPTY_STRUCTURE_MEMBER
    }

    /// The class name Python shows: the last part of the type name.
    pub fn short_name(&self) -> &str {
        self.name.rsplit('/').next().unwrap_or(&self.name)
    }
}

/// A dynamic value. Structs hold their fields in member order.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// `bool`.
    Bool(bool),
    /// Any integer type (range-checked against the field).
    Int(i128),
    /// `float32` / `float64`.
    Float(f64),
    /// `string`, `wstring`, `char`, `wchar`.
    Str(String),
    /// `byte`.
    Byte(u8),
    /// An array or a sequence.
    List(Vec<Value>),
    /// A nested message.
    Struct(Vec<Value>),
}

/// Why a [`FieldType`] of a description has no [`FieldTy`] ([`convert_type`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FieldTypeError {
    /// The type id is none of `type_description_interfaces/msg/FieldType`'s.
    #[error("unknown field type id {type_id}")]
    UnknownTypeId {
        /// The id found.
        type_id: u8,
    },
    /// An array or sequence capacity that does not fit a `usize`.
    #[error("capacity {capacity} is too large")]
    CapacityTooLarge {
        /// The capacity found.
        capacity: u64,
    },
    /// A nested type with an empty `nested_type_name`.
    #[error("nested type without a name")]
    UnnamedNestedType,
}

/// Why a description makes no [`Schema`], or a type of a schema cannot be used
/// ([`Schema::from_description`], [`Schema::check`], [`Schema::default_value`],
/// [`sub_description`], [`ServiceType::from_descriptions`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SchemaError {
    /// A type used (or asked for) is not in the description.
    #[error("the type description lacks type '{type_name}'")]
    MissingType {
        /// The type's name (`pkg/msg/Name`).
        type_name: String,
    },
    /// A field's type does not convert.
    #[error("field '{field}' of '{type_name}': {cause}")]
    FieldType {
        /// The struct holding the field.
        type_name: String,
        /// The field's name.
        field: String,
        /// What is wrong with its type.
        cause: FieldTypeError,
    },
    /// A type contains itself (directly or through other types).
    #[error("type '{type_name}' contains itself")]
    Recursive {
        /// The type found again inside itself.
        type_name: String,
    },
    /// Structs nest deeper than [`MAX_NESTING`].
    #[error("type '{type_name}' nests structs more than {} deep", MAX_NESTING)]
    TooDeep {
        /// The outermost type.
        type_name: String,
    },
    /// A struct without fields (rosidl always gives one a placeholder field).
    #[error("type '{type_name}' has no fields")]
    NoFields {
        /// The struct.
        type_name: String,
    },
    /// A fixed array of no element.
    #[error("field '{field}' of '{type_name}' is an array of 0 elements")]
    EmptyArray {
        /// The struct holding the field.
        type_name: String,
        /// The field's name.
        field: String,
    },
    /// A value of the type would hold more than [`MAX_FIXED_VALUES`] values outside sequences.
    #[error(
        "type '{type_name}' holds more than {} values in fixed-size fields",
        MAX_FIXED_VALUES
    )]
    TooManyValues {
        /// The type found too large.
        type_name: String,
    },
}

impl SchemaError {
    /// A [`SchemaError::MissingType`] for `type_name`.
    fn missing(type_name: &str) -> Self {
        Self::MissingType {
            type_name: type_name.to_owned(),
        }
    }
}

/// The struct types of one or more descriptions, by name.
#[derive(Clone, Debug, Default)]
pub struct Schema {
    structs: HashMap<String, Struct>,
}

impl Schema {
    /// The main type and every referenced type of `description`.
    pub fn from_description(description: &TypeDescription) -> Result<Self, SchemaError> {
        let mut schema = Self::default();
        schema.add(description)?;
        Ok(schema)
    }

    /// Adds the types of another description.
    pub fn add(&mut self, description: &TypeDescription) -> Result<(), SchemaError> {
        for t in std::iter::once(&description.type_description)
            .chain(&description.referenced_type_descriptions)
        {
            let s = convert_struct(t)?;
            self.structs.insert(s.name.clone(), s);
        }
        Ok(())
    }

    /// A struct by name.
    pub fn get(&self, name: &str) -> Result<&Struct, SchemaError> {
        self.structs
            .get(name)
            .ok_or_else(|| SchemaError::missing(name))
    }

    /// Checks that type `root` can be used: every nested type it uses (recursively) is known,
    /// none contains itself, every struct has a field and every fixed array an element (as
    /// rosidl guarantees: rosidl_adapter `parser.py` takes only array sizes `> 0`, rosidl_parser
    /// gives empty structs a placeholder member), structs nest at most [`MAX_NESTING`] deep and
    /// a value of the type holds at most [`MAX_FIXED_VALUES`] values outside sequences.
    ///
    /// Descriptions come from the network: these bounds are what keep [`Schema::default_value`],
    /// [`cdr::decode`] and the printers from recursing without end, allocating without bound or
    /// decoding elements that take no bytes. Call it before using a type.
    pub fn check(&self, root: &str) -> Result<(), SchemaError> {
        self.check_struct(root, &mut Vec::new(), &mut HashMap::new())
            .map(|_values| ())
    }

    /// The number of values in a `name` outside sequences (fixed arrays and nested structs
    /// counted with their elements), once its types are checked; `done` remembers the types
    /// already checked, `path` the structs being checked around this one.
    fn check_struct<'a>(
        &'a self,
        name: &'a str,
        path: &mut Vec<&'a str>,
        done: &mut HashMap<&'a str, u64>,
    ) -> Result<u64, SchemaError> {
        if let Some(values) = done.get(name) {
            return Ok(*values);
        }
        if path.contains(&name) {
            return Err(SchemaError::Recursive {
                type_name: name.to_owned(),
            });
        }
        if path.len() >= MAX_NESTING {
            return Err(SchemaError::TooDeep {
                type_name: path[0].to_owned(),
            });
        }
        let s = self.get(name)?;
        if s.members.is_empty() {
            return Err(SchemaError::NoFields {
                type_name: name.to_owned(),
            });
        }
        path.push(name);
        let mut values: u64 = 1;
        for m in &s.members {
            let element = match &m.ty.elem {
                Elem::Nested(n) => self.check_struct(n, path, done)?,
                _ => 1,
            };
            let member = match m.ty.container {
                Container::Single => element,
                Container::Array(0) => {
                    return Err(SchemaError::EmptyArray {
                        type_name: name.to_owned(),
                        field: m.name.clone(),
                    })
                }
                Container::Array(n) => 1u64
                    .saturating_add(u64::try_from(n).unwrap_or(u64::MAX).saturating_mul(element)),
                Container::Sequence(_) => 1,
            };
            values = values.saturating_add(member);
            if values > MAX_FIXED_VALUES {
                return Err(SchemaError::TooManyValues {
                    type_name: name.to_owned(),
                });
            }
        }
        path.pop();
        done.insert(name, values);
        Ok(values)
    }

    /// The default value of struct `name`: each field's `.msg` default, else zero / empty
    /// (after [`Schema::check`] of `name`).
    pub fn default_value(&self, name: &str) -> Result<Value, SchemaError> {
        self.check(name)?;
        self.checked_default(name)
    }

    /// [`Schema::default_value`] of a type already checked.
    fn checked_default(&self, name: &str) -> Result<Value, SchemaError> {
        let s = self.get(name)?;
        let mut fields = Vec::with_capacity(s.members.len());
        for m in &s.members {
            fields.push(self.member_default(m)?);
        }
        Ok(Value::Struct(fields))
    }

    /// A member's default value.
    fn member_default(&self, m: &Member) -> Result<Value, SchemaError> {
        if !m.default.is_empty() {
            if let Some(v) = yaml::parse_default(self, m) {
                return Ok(v);
            }
        }
        match m.ty.container {
            Container::Single => self.elem_default(&m.ty.elem),
            Container::Array(n) => {
                let e = self.elem_default(&m.ty.elem)?;
                Ok(Value::List(vec![e; n]))
            }
            Container::Sequence(_) => Ok(Value::List(Vec::new())),
        }
    }

    /// The zero value of an element.
    fn elem_default(&self, e: &Elem) -> Result<Value, SchemaError> {
        Ok(match e {
            Elem::Bool => Value::Bool(false),
            Elem::Byte => Value::Byte(0),
            Elem::Char | Elem::WChar => Value::Str("\0".to_owned()),
            Elem::Int { .. } => Value::Int(0),
            Elem::F32 | Elem::F64 | Elem::LongDouble => Value::Float(0.0),
            Elem::Str(_) | Elem::WStr(_) => Value::Str(String::new()),
            Elem::Nested(n) => self.checked_default(n)?,
        })
    }
}

/// The sub-description of `type_name` out of `description`'s referenced types: that type plus
/// everything it references (recursively), sorted by name — what its own RIHS01 hash covers.
pub fn sub_description(
    description: &TypeDescription,
    type_name: &str,
) -> Result<TypeDescription, SchemaError> {
    let all: HashMap<&str, &IndividualTypeDescription> =
        std::iter::once(&description.type_description)
            .chain(&description.referenced_type_descriptions)
            .map(|t| (t.type_name.as_str(), t))
            .collect();
    let main = *all
        .get(type_name)
        .ok_or_else(|| SchemaError::missing(type_name))?;
    let mut seen: Vec<String> = Vec::new();
    let mut stack: Vec<&IndividualTypeDescription> = vec![main];
    while let Some(t) = stack.pop() {
        for f in &t.fields {
            let n = &f.r#type.nested_type_name;
            if n.is_empty() || seen.contains(n) || n == type_name {
                continue;
            }
            let r = all.get(n.as_str()).ok_or_else(|| SchemaError::missing(n))?;
            seen.push(n.clone());
            stack.push(r);
        }
    }
    seen.sort();
    Ok(TypeDescription {
        type_description: main.clone(),
        referenced_type_descriptions: seen
            .iter()
            .filter_map(|n| all.get(n.as_str()).map(|t| (*t).clone()))
            .collect(),
    })
}

fn convert_struct(t: &IndividualTypeDescription) -> Result<Struct, SchemaError> {
    let members = t
        .fields
        .iter()
        .map(|f| {
            Ok(Member {
                name: f.name.clone(),
                ty: convert_type(&f.r#type).map_err(|source| SchemaError::FieldType {
                    type_name: t.type_name.clone(),
                    field: f.name.clone(),
                    cause: source,
                })?,
                default: f.default_value.clone(),
            })
        })
        .collect::<Result<Vec<_>, SchemaError>>()?;
    Ok(Struct {
        name: t.type_name.clone(),
        members,
    })
}

fn usize_of(n: u64) -> Result<usize, FieldTypeError> {
    usize::try_from(n).map_err(|_| FieldTypeError::CapacityTooLarge { capacity: n })
}

/// Maps a `FieldType` to [`FieldTy`].
pub fn convert_type(t: &FieldType) -> Result<FieldTy, FieldTypeError> {
    let (base, container) = match t.type_id {
        1..=48 => (t.type_id, Container::Single),
        49..=96 => (t.type_id - 48, Container::Array(usize_of(t.capacity)?)),
        97..=144 => (
            t.type_id - 96,
            Container::Sequence(Some(usize_of(t.capacity)?)),
        ),
        145..=192 => (t.type_id - 144, Container::Sequence(None)),
        id => return Err(FieldTypeError::UnknownTypeId { type_id: id }),
    };
    let bound = (t.string_capacity > 0).then_some(t.string_capacity);
    let elem = match base {
        FieldType::FIELD_TYPE_NESTED_TYPE => {
            if t.nested_type_name.is_empty() {
                return Err(FieldTypeError::UnnamedNestedType);
            }
            Elem::Nested(t.nested_type_name.clone())
        }
        FieldType::FIELD_TYPE_INT8 => Elem::Int {
            bits: 8,
            signed: true,
        },
        FieldType::FIELD_TYPE_UINT8 => Elem::Int {
            bits: 8,
            signed: false,
        },
        FieldType::FIELD_TYPE_INT16 => Elem::Int {
            bits: 16,
            signed: true,
        },
        FieldType::FIELD_TYPE_UINT16 => Elem::Int {
            bits: 16,
            signed: false,
        },
        FieldType::FIELD_TYPE_INT32 => Elem::Int {
            bits: 32,
            signed: true,
        },
        FieldType::FIELD_TYPE_UINT32 => Elem::Int {
            bits: 32,
            signed: false,
        },
        FieldType::FIELD_TYPE_INT64 => Elem::Int {
            bits: 64,
            signed: true,
        },
        FieldType::FIELD_TYPE_UINT64 => Elem::Int {
            bits: 64,
            signed: false,
        },
        FieldType::FIELD_TYPE_FLOAT => Elem::F32,
        FieldType::FIELD_TYPE_DOUBLE => Elem::F64,
        FieldType::FIELD_TYPE_LONG_DOUBLE => Elem::LongDouble,
        FieldType::FIELD_TYPE_CHAR => Elem::Char,
        FieldType::FIELD_TYPE_WCHAR => Elem::WChar,
        FieldType::FIELD_TYPE_BOOLEAN => Elem::Bool,
        FieldType::FIELD_TYPE_BYTE => Elem::Byte,
        FieldType::FIELD_TYPE_STRING => Elem::Str(None),
        FieldType::FIELD_TYPE_WSTRING => Elem::WStr(None),
        FieldType::FIELD_TYPE_FIXED_STRING | FieldType::FIELD_TYPE_BOUNDED_STRING => {
            Elem::Str(bound)
        }
        FieldType::FIELD_TYPE_FIXED_WSTRING | FieldType::FIELD_TYPE_BOUNDED_WSTRING => {
            Elem::WStr(bound)
        }
        id => return Err(FieldTypeError::UnknownTypeId { type_id: id }),
    };
    Ok(FieldTy { elem, container })
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_msgs::rcl_interfaces::srv::SetParameters;
    use horus_ros_msgs::{Field, Message, Service};

    /// A field of `type_id` (`capacity` for arrays), nested type `nested` if not empty.
    fn field(name: &str, type_id: u8, capacity: u64, nested: &str) -> Field {
        Field {
            name: name.to_owned(),
            r#type: FieldType {
                type_id,
                capacity,
                string_capacity: 0,
                nested_type_name: nested.to_owned(),
            },
            default_value: String::new(),
        }
    }

    #[test]
    fn char_values_fit_their_eight_or_sixteen_bits() {
        // A `char` default beyond 8 bits once filled a value the encoder refused (found by
        // fuzzing): such a default is not used.
        let mut c = field("c", FieldType::FIELD_TYPE_CHAR, 0, "");
        c.default_value = "\u{100}".to_owned();
        let w = field("w", FieldType::FIELD_TYPE_WCHAR, 0, "");
        let d = description(vec![("p/msg/C".to_owned(), vec![c, w])]);
        let schema = Schema::from_description(&d).expect("schema");
        let value = schema.default_value("p/msg/C").expect("default");
        assert_eq!(
            value,
            Value::Struct(vec![
                Value::Str("\0".to_owned()),
                Value::Str("\0".to_owned())
            ])
        );
        assert!(cdr::encode(&schema, "p/msg/C", &value).is_ok());
        let filled = yaml::fill_from_yaml(&schema, "p/msg/C", "{c: 'é', w: '€'}").expect("fits");
        let body = cdr::encode(&schema, "p/msg/C", &filled).expect("encodes");
        assert_eq!(cdr::decode(&schema, "p/msg/C", &body, false), Ok(filled));
        assert!(yaml::fill_from_yaml(&schema, "p/msg/C", "{c: '€'}").is_err());
        assert!(yaml::fill_from_yaml(&schema, "p/msg/C", "{w: '😀'}").is_err());
        assert!(yaml::fill_from_yaml(&schema, "p/msg/C", "{c: 300}").is_err());
    }

    /// A description of `types` (name, fields), the first being the main one.
    fn description(types: Vec<(String, Vec<Field>)>) -> TypeDescription {
        let mut all = types
            .into_iter()
            .map(|(type_name, fields)| IndividualTypeDescription { type_name, fields });
        let main = all.next().expect("a main type");
        TypeDescription {
            type_description: main,
            referenced_type_descriptions: all.collect(),
        }
    }

    fn check_error(types: Vec<(String, Vec<Field>)>) -> String {
        let d = description(types);
        let root = d.type_description.type_name.clone();
        let schema = Schema::from_description(&d).expect("fields convert");
        let error = schema.check(&root).expect_err("refused");
        assert_eq!(
            schema.default_value(&root).expect_err("no default either"),
            error
        );
        error.to_string()
    }

    const NESTED_ARRAY: u8 = FieldType::FIELD_TYPE_NESTED_TYPE + 48;
    const UINT8_ARRAY: u8 = FieldType::FIELD_TYPE_UINT8 + 48;

    #[test]
    fn a_huge_fixed_array_is_refused_before_anything_is_allocated() {
        // What fuzzing found (fuzz/regressions/dynamic_description/fixed_array_*): a description
        // claiming `uint8[2^62]` made the default value allocate it.
        let e = check_error(vec![(
            "p/msg/A".into(),
            vec![field("data", UINT8_ARRAY, 1 << 62, "")],
        )]);
        assert!(e.contains("more than 1048576 values"), "{e}");
        // Within the bound: materialized.
        let d = description(vec![(
            "p/msg/A".into(),
            vec![field("data", UINT8_ARRAY, 1000, "")],
        )]);
        let schema = Schema::from_description(&d).expect("schema");
        assert!(schema.check("p/msg/A").is_ok());
        let Value::Struct(fields) = schema.default_value("p/msg/A").expect("default") else {
            panic!("not a struct")
        };
        assert_eq!(fields, vec![Value::List(vec![Value::Int(0); 1000])]);
    }

    #[test]
    fn nested_fixed_arrays_multiply() {
        // 1024 × 1024 values of B in A: over the bound although each array is small.
        let e = check_error(vec![
            (
                "p/msg/A".into(),
                vec![field("b", NESTED_ARRAY, 1024, "p/msg/B")],
            ),
            ("p/msg/B".into(), vec![field("data", UINT8_ARRAY, 1024, "")]),
        ]);
        assert!(e.contains("'p/msg/A' holds more than"), "{e}");
    }

    #[test]
    fn fan_out_without_arrays_is_counted_once_per_type() {
        // T0 holds two T1, T1 two T2, … T40: 2^40 values, and a walk that did not remember
        // the types it checked would take 2^40 steps.
        let types: Vec<(String, Vec<Field>)> = (0..=40)
            .map(|i| {
                let fields = if i == 40 {
                    vec![field("x", FieldType::FIELD_TYPE_UINT8, 0, "")]
                } else {
                    let next = format!("p/msg/T{}", i + 1);
                    vec![
                        field("l", FieldType::FIELD_TYPE_NESTED_TYPE, 0, &next),
                        field("r", FieldType::FIELD_TYPE_NESTED_TYPE, 0, &next),
                    ]
                };
                (format!("p/msg/T{i}"), fields)
            })
            .collect();
        let e = check_error(types);
        assert!(e.contains("more than 1048576 values"), "{e}");
    }

    #[test]
    fn deep_nesting_and_cycles_are_refused() {
        let chain = |n: usize| -> Vec<(String, Vec<Field>)> {
            (0..n)
                .map(|i| {
                    let fields = if i + 1 == n {
                        vec![field("x", FieldType::FIELD_TYPE_UINT8, 0, "")]
                    } else {
                        let next = format!("p/msg/T{}", i + 1);
                        vec![field("n", FieldType::FIELD_TYPE_NESTED_TYPE, 0, &next)]
                    };
                    (format!("p/msg/T{i}"), fields)
                })
                .collect()
        };
        let d = description(chain(MAX_NESTING));
        let schema = Schema::from_description(&d).expect("schema");
        assert!(schema.check("p/msg/T0").is_ok());
        let e = check_error(chain(MAX_NESTING + 1));
        assert!(e.contains("nests structs more than 100 deep"), "{e}");
        let e = check_error(vec![
            (
                "p/msg/A".into(),
                vec![field("b", FieldType::FIELD_TYPE_NESTED_TYPE, 0, "p/msg/B")],
            ),
            (
                "p/msg/B".into(),
                vec![field("a", NESTED_ARRAY, 2, "p/msg/A")],
            ),
        ]);
        assert!(e.contains("contains itself"), "{e}");
    }

    #[test]
    fn structs_without_fields_and_empty_arrays_are_refused() {
        // Both would make elements that take no byte: a sequence count could not be checked
        // against the bytes left.
        let e = check_error(vec![
            (
                "p/msg/A".into(),
                vec![field("b", FieldType::FIELD_TYPE_NESTED_TYPE, 0, "p/msg/B")],
            ),
            ("p/msg/B".into(), Vec::new()),
        ]);
        assert!(e.contains("'p/msg/B' has no fields"), "{e}");
        let e = check_error(vec![(
            "p/msg/A".into(),
            vec![field("data", UINT8_ARRAY, 0, "")],
        )]);
        assert!(e.contains("array of 0 elements"), "{e}");
    }

    #[test]
    fn decoding_an_unchecked_recursive_type_is_an_error_not_a_stack_overflow() {
        let d = description(vec![(
            "p/msg/A".into(),
            vec![
                field("x", FieldType::FIELD_TYPE_UINT8, 0, ""),
                field("a", FieldType::FIELD_TYPE_NESTED_TYPE, 0, "p/msg/A"),
            ],
        )]);
        let schema = Schema::from_description(&d).expect("schema");
        let e = cdr::decode(&schema, "p/msg/A", &[0; 4096], false).expect_err("refused");
        assert!(
            matches!(&e, cdr::DecodeError::TooDeep { type_name } if type_name == "p/msg/A"),
            "{e:?}"
        );
        assert!(e.to_string().contains("more than 100 deep"), "{e}");
    }

    #[test]
    fn counts_larger_than_the_bytes_left_are_refused_at_once() {
        let d = description(vec![(
            "p/msg/A".into(),
            vec![
                field("data", UINT8_ARRAY, 1000, ""),
                field("s", FieldType::FIELD_TYPE_UINT8 + 144, 0, ""),
            ],
        )]);
        let schema = Schema::from_description(&d).expect("schema");
        assert!(cdr::decode(&schema, "p/msg/A", &[0; 999], false).is_err());
        let mut body = vec![0; 1000];
        body.extend_from_slice(&u32::MAX.to_le_bytes());
        let e = cdr::decode(&schema, "p/msg/A", &body, false).expect_err("refused");
        assert_eq!(
            e,
            cdr::DecodeError::SequenceTooLong {
                field: "s".to_owned(),
                len: 4294967295,
                bound: None,
            }
        );
        assert!(
            e.to_string().contains("sequence of 4294967295 elements"),
            "{e}"
        );
        body.truncate(1000);
        body.extend_from_slice(&2u32.to_le_bytes());
        body.extend_from_slice(&[7, 8]);
        let Value::Struct(fields) = cdr::decode(&schema, "p/msg/A", &body, false).expect("fits")
        else {
            panic!("not a struct")
        };
        assert_eq!(fields[1], Value::List(vec![Value::Int(7), Value::Int(8)]));
    }

    #[test]
    fn sub_description_of_a_service_part_hashes_like_the_compiled_type() {
        let service = SetParameters::type_description();
        let req =
            sub_description(&service, "rcl_interfaces/srv/SetParameters_Request").expect("request");
        assert_eq!(
            req.compute_type_hash(),
            <SetParameters as Service>::Request::type_hash()
        );
        let schema = Schema::from_description(&service).expect("schema");
        schema
            .check("rcl_interfaces/srv/SetParameters_Request")
            .expect("complete");
    }
}
