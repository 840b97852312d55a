//! Type descriptions (`type_description_interfaces/msg/TypeDescription`) and RIHS01 hashes of
//! parsed interfaces, as rosidl_generator_type_description (jazzy) `__init__.py` builds them:
//! `add_msg` / `add_srv` / `add_action` register every type an interface defines (a service's
//! `_Event`, an action's `_SendGoal`, `_GetResult` and `_FeedbackMessage` from rosidl_parser
//! `definition.py`), `serialize_field` gives each field its type and default, and
//! `extract_full_type_description` collects what a type references, sorted by name.

use std::collections::{BTreeMap, BTreeSet};

use horus_ros_dynamic::repr::{py_float, py_str};
use horus_ros_msgs::description::EMPTY_STRUCTURE_MEMBER;
use horus_ros_msgs::rihs::rihs01;
use horus_ros_msgs::type_description_interfaces::msg::{
    Field as DescribedField, FieldType as DescribedType, IndividualTypeDescription, TypeDescription,
};
use horus_ros_msgs::TypeHash;

use crate::definition::{
    Action, BaseType, Container, Field, FieldType, Interface, Literal, Message, NamedType,
    Primitive, Service, Value,
};

/// The goal id every action message carries (rosidl_parser `Action.__init__`).
pub const GOAL_ID_TYPE: (&str, &str, &str) = ("unique_identifier_msgs", "msg", "UUID");
/// The time stamp type of a `SendGoal` response.
pub const TIME_TYPE: (&str, &str, &str) = ("builtin_interfaces", "msg", "Time");
/// What a service's `_Event` message starts with.
pub const SERVICE_EVENT_INFO_TYPE: (&str, &str, &str) = ("service_msgs", "msg", "ServiceEventInfo");

/// Errors of [`TypeRegistry::describe`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DescribeError {
    /// No interface defines the type asked for.
    #[error("unknown type '{0}'")]
    Unknown(String),
    /// A type it references (directly or not) is not known.
    #[error(
        "type '{referenced}', used by '{user}', is unknown (is its package among the inputs?)"
    )]
    UnknownReference {
        /// The type referenced.
        referenced: String,
        /// The type whose field references it.
        user: String,
    },
}

/// Every type of a set of interfaces, by name, ready to be described.
#[derive(Debug, Clone, Default)]
pub struct TypeRegistry {
    types: BTreeMap<String, IndividualTypeDescription>,
}

impl TypeRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers every type `interface` defines (rosidl `add_msg` / `add_srv` / `add_action`).
    pub fn add(&mut self, interface: &Interface) {
        match interface {
            Interface::Message(m) => self.add_message(m),
            Interface::Service(s) => self.add_service(s),
            Interface::Action(a) => self.add_action(a),
        }
    }

    /// Registers the types of a description (e.g. a compiled type's, or one read off a live
    /// node), keeping types already known.
    pub fn add_description(&mut self, description: &TypeDescription) {
        for t in std::iter::once(&description.type_description)
            .chain(&description.referenced_type_descriptions)
        {
            self.types
                .entry(t.type_name.clone())
                .or_insert_with(|| t.clone());
        }
    }

    /// Whether `type_name` is known.
    pub fn contains(&self, type_name: &str) -> bool {
        self.types.contains_key(type_name)
    }

    /// Every known type name, sorted.
    pub fn type_names(&self) -> impl Iterator<Item = &str> {
        self.types.keys().map(String::as_str)
    }

    /// The full description of `type_name`: the type and everything it references, sorted by
    /// name (rosidl `extract_full_type_description`).
    pub fn describe(&self, type_name: &str) -> Result<TypeDescription, DescribeError> {
        let main = self
            .types
            .get(type_name)
            .ok_or_else(|| DescribeError::Unknown(type_name.to_owned()))?;
        let mut referenced = BTreeSet::new();
        let mut queue: Vec<(&str, &str)> = nested_names(main).map(|n| (n, type_name)).collect();
        while let Some((name, user)) = queue.pop() {
            if referenced.insert(name) {
                let t = self
                    .types
                    .get(name)
                    .ok_or_else(|| DescribeError::UnknownReference {
                        referenced: name.to_owned(),
                        user: user.to_owned(),
                    })?;
                queue.extend(nested_names(t).map(|n| (n, name)));
            }
        }
        Ok(TypeDescription {
            type_description: main.clone(),
            // BTreeSet order is byte order, as Python's `sorted` of str.
            referenced_type_descriptions: referenced
                .into_iter()
                .filter_map(|n| self.types.get(n).cloned())
                .collect(),
        })
    }

    /// The RIHS01 hash of `type_name`'s full description.
    pub fn hash(&self, type_name: &str) -> Result<TypeHash, DescribeError> {
        self.describe(type_name).map(|d| rihs01(&d))
    }

    fn insert(&mut self, name: &NamedType, fields: Vec<DescribedField>) {
        let name = name.to_string();
        self.types.insert(
            name.clone(),
            IndividualTypeDescription {
                type_name: name,
                fields,
            },
        );
    }

    fn add_message(&mut self, m: &Message) {
        let mut fields: Vec<DescribedField> = m.fields.iter().map(describe_field).collect();
        if fields.is_empty() {
            fields.push(plain_field(
                EMPTY_STRUCTURE_MEMBER,
                single(BaseType::Primitive(Primitive::UInt8)),
            ));
        }
        self.insert(&m.name, fields);
    }

    fn add_service(&mut self, s: &Service) {
        let event = event_message(s);
        self.insert(
            &s.name,
            vec![
                nested_field("request_message", &s.request.name),
                nested_field("response_message", &s.response.name),
                nested_field("event_message", &event.name),
            ],
        );
        self.add_message(&s.request);
        self.add_message(&s.response);
        self.add_message(&event);
    }

    fn add_action(&mut self, a: &Action) {
        let derived = ActionTypes::of(a);
        self.insert(
            &a.name,
            vec![
                nested_field("goal", &a.goal.name),
                nested_field("result", &a.result.name),
                nested_field("feedback", &a.feedback.name),
                nested_field("send_goal_service", &derived.send_goal.name),
                nested_field("get_result_service", &derived.get_result.name),
                nested_field("feedback_message", &derived.feedback_message.name),
            ],
        );
        self.add_message(&a.goal);
        self.add_message(&a.result);
        self.add_message(&a.feedback);
        self.add_service(&derived.send_goal);
        self.add_service(&derived.get_result);
        self.add_message(&derived.feedback_message);
    }
}

/// The types rcl_action uses for an action (rosidl_parser `Action.__init__`).
#[derive(Debug, Clone, PartialEq)]
pub struct ActionTypes {
    /// `Name_SendGoal`: request `goal_id`, `goal`; response `accepted`, `stamp`.
    pub send_goal: Service,
    /// `Name_GetResult`: request `goal_id`; response `status`, `result`.
    pub get_result: Service,
    /// `Name_FeedbackMessage`: `goal_id`, `feedback`.
    pub feedback_message: Message,
}

impl ActionTypes {
    /// Derives them from `action`.
    pub fn of(action: &Action) -> Self {
        let goal_id = || member("goal_id", named(GOAL_ID_TYPE));
        let send_goal = action.name.with_suffix("_SendGoal");
        let get_result = action.name.with_suffix("_GetResult");
        Self {
            send_goal: Service {
                request: struct_of(
                    send_goal.with_suffix("_Request"),
                    vec![
                        goal_id(),
                        member("goal", BaseType::Named(action.goal.name.clone())),
                    ],
                ),
                response: struct_of(
                    send_goal.with_suffix("_Response"),
                    vec![
                        member("accepted", BaseType::Primitive(Primitive::Bool)),
                        member("stamp", named(TIME_TYPE)),
                    ],
                ),
                name: send_goal,
            },
            get_result: Service {
                request: struct_of(get_result.with_suffix("_Request"), vec![goal_id()]),
                response: struct_of(
                    get_result.with_suffix("_Response"),
                    vec![
                        member("status", BaseType::Primitive(Primitive::Int8)),
                        member("result", BaseType::Named(action.result.name.clone())),
                    ],
                ),
                name: get_result,
            },
            feedback_message: struct_of(
                action.name.with_suffix("_FeedbackMessage"),
                vec![
                    goal_id(),
                    member("feedback", BaseType::Named(action.feedback.name.clone())),
                ],
            ),
        }
    }
}

/// A service's `Name_Event`: `info`, `request[<=1]`, `response[<=1]` (rosidl_parser
/// `Service.__init__`).
pub fn event_message(service: &Service) -> Message {
    // `request` and `response`: `Name_Request[<=1]`, `Name_Response[<=1]`.
    let at_most_one = |name: &str, t: &NamedType| Field {
        ty: FieldType {
            base: BaseType::Named(t.clone()),
            container: Container::BoundedSequence(1),
        },
        ..member(name, BaseType::Named(t.clone()))
    };
    struct_of(
        service.name.with_suffix("_Event"),
        vec![
            member("info", named(SERVICE_EVENT_INFO_TYPE)),
            at_most_one("request", &service.request.name),
            at_most_one("response", &service.response.name),
        ],
    )
}

fn named((package, namespace, name): (&str, &str, &str)) -> BaseType {
    BaseType::Named(NamedType::new(package, namespace, name))
}

fn member(name: &str, base: BaseType) -> Field {
    Field {
        name: name.to_owned(),
        ty: single(base),
        default: None,
        comment: Vec::new(),
        unit: None,
    }
}

fn struct_of(name: NamedType, fields: Vec<Field>) -> Message {
    Message {
        name,
        fields,
        constants: Vec::new(),
        comment: Vec::new(),
    }
}

fn single(base: BaseType) -> FieldType {
    FieldType::single(base)
}

fn nested_names(t: &IndividualTypeDescription) -> impl Iterator<Item = &str> {
    t.fields
        .iter()
        .map(|f| f.r#type.nested_type_name.as_str())
        .filter(|n| !n.is_empty())
}

fn nested_field(name: &str, t: &NamedType) -> DescribedField {
    plain_field(name, single(BaseType::Named(t.clone())))
}

fn plain_field(name: &str, ty: FieldType) -> DescribedField {
    DescribedField {
        name: name.to_owned(),
        r#type: field_type(&ty),
        default_value: String::new(),
    }
}

/// rosidl `serialize_field`.
fn describe_field(f: &Field) -> DescribedField {
    DescribedField {
        name: f.name.clone(),
        r#type: field_type(&f.ty),
        default_value: f
            .default
            .as_ref()
            .map(default_value_text)
            .unwrap_or_default(),
    }
}

/// rosidl `serialize_field_type`: the type id (element id plus 48 for arrays, 96 for bounded
/// and 144 for unbounded sequences), capacity, string capacity and nested type name.
pub fn field_type(ty: &FieldType) -> DescribedType {
    let (elem, string_capacity, nested) = match &ty.base {
        BaseType::Primitive(p) => (primitive_id(*p), 0, String::new()),
        BaseType::String(None) => (DescribedType::FIELD_TYPE_STRING, 0, String::new()),
        BaseType::String(Some(n)) => (DescribedType::FIELD_TYPE_BOUNDED_STRING, *n, String::new()),
        BaseType::WString(None) => (DescribedType::FIELD_TYPE_WSTRING, 0, String::new()),
        BaseType::WString(Some(n)) => {
            (DescribedType::FIELD_TYPE_BOUNDED_WSTRING, *n, String::new())
        }
        BaseType::Named(t) => (DescribedType::FIELD_TYPE_NESTED_TYPE, 0, t.to_string()),
    };
    let (offset, capacity) = match ty.container {
        Container::Single => (0, 0),
        Container::Array(n) => (48, n),
        Container::BoundedSequence(n) => (96, n),
        Container::UnboundedSequence => (144, 0),
    };
    DescribedType {
        type_id: elem + offset,
        capacity,
        string_capacity,
        nested_type_name: nested,
    }
}

fn primitive_id(p: Primitive) -> u8 {
    match p {
        Primitive::Bool => DescribedType::FIELD_TYPE_BOOLEAN,
        Primitive::Byte => DescribedType::FIELD_TYPE_BYTE,
        Primitive::Char => DescribedType::FIELD_TYPE_CHAR,
        Primitive::WChar => DescribedType::FIELD_TYPE_WCHAR,
        Primitive::Float32 => DescribedType::FIELD_TYPE_FLOAT,
        Primitive::Float64 => DescribedType::FIELD_TYPE_DOUBLE,
        Primitive::LongDouble => DescribedType::FIELD_TYPE_LONG_DOUBLE,
        Primitive::Int8 => DescribedType::FIELD_TYPE_INT8,
        Primitive::UInt8 => DescribedType::FIELD_TYPE_UINT8,
        Primitive::Int16 => DescribedType::FIELD_TYPE_INT16,
        Primitive::UInt16 => DescribedType::FIELD_TYPE_UINT16,
        Primitive::Int32 => DescribedType::FIELD_TYPE_INT32,
        Primitive::UInt32 => DescribedType::FIELD_TYPE_UINT32,
        Primitive::Int64 => DescribedType::FIELD_TYPE_INT64,
        Primitive::UInt64 => DescribedType::FIELD_TYPE_UINT64,
    }
}

/// A default as rosidl writes it into descriptions: Python `str()` of the `@default` value, so
/// `True`, `-50`, `1.125`, the string itself, and for arrays the Python `repr` of the tuple
/// (`(1, 2, 3)`, `('a', 'b')`), which rosidl_adapter stores as a string.
pub fn default_value_text(v: &Value) -> String {
    match v {
        Value::Scalar(Literal::String(s)) => s.clone(),
        Value::Scalar(l) => python_repr(l),
        Value::Array(items) => match items.as_slice() {
            [one] => format!("({},)", python_repr(one)),
            _ => format!(
                "({})",
                items.iter().map(python_repr).collect::<Vec<_>>().join(", ")
            ),
        },
    }
}

/// Python `repr()` of a literal.
pub fn python_repr(l: &Literal) -> String {
    match l {
        Literal::Bool(true) => "True".to_owned(),
        Literal::Bool(false) => "False".to_owned(),
        Literal::Int(i) => i.to_string(),
        Literal::Float(f) => py_float(*f),
        Literal::String(s) => py_str(s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_and_tuples_print_as_python_repr() {
        let v = Value::Array(vec![
            Literal::String("it's".into()),
            Literal::String("a\\b".into()),
        ]);
        assert_eq!(default_value_text(&v), "(\"it's\", 'a\\\\b')");
        let v = Value::Array(vec![Literal::Int(1)]);
        assert_eq!(default_value_text(&v), "(1,)");
        let v = Value::Array(vec![]);
        assert_eq!(default_value_text(&v), "()");
        let v = Value::Array(vec![Literal::Bool(false), Literal::Float(1.0)]);
        assert_eq!(default_value_text(&v), "(False, 1.0)");
    }
}
