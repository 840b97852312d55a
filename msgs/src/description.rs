//! Building `type_description_interfaces/msg/TypeDescription` values the way
//! rosidl_generator_type_description (jazzy) `__init__.py` does (`serialize_field`,
//! `extract_full_type_description`, `add_srv`; the event message from rosidl_parser
//! `definition.py` `Service.__init__`).

use crate::field::RosField;
use crate::type_description_interfaces::msg::{
    Field, FieldType, IndividualTypeDescription, TypeDescription,
};

/// Name of the placeholder member rosidl gives empty structures (rosidl_parser
/// `EMPTY_STRUCTURE_REQUIRED_MEMBER_NAME`; added as `uint8` by rosidl_adapter `struct.idl.em`).
pub const EMPTY_STRUCTURE_MEMBER: &str = "structure_needs_at_least_one_member";

/// Builds the [`TypeDescription`] of one message type field by field.
#[derive(Debug, Clone)]
pub struct DescriptionBuilder {
    main: IndividualTypeDescription,
    referenced: Vec<IndividualTypeDescription>,
}

impl DescriptionBuilder {
    /// Starts a description of `type_name` (`pkg/msg/Name` or `pkg/srv/Name_Request`…).
    pub fn new(type_name: &str) -> Self {
        Self {
            main: IndividualTypeDescription {
                type_name: type_name.to_owned(),
                fields: Vec::new(),
            },
            referenced: Vec::new(),
        }
    }

    /// Appends a field described by its Rust type.
    pub fn field<T: RosField>(self, name: &str) -> Self {
        self.field_with::<T>(name, |t| t)
    }

    /// Appends a field described by its Rust type, adjusted by `modify` (e.g. bounds).
    /// A raw identifier's `r#` prefix is dropped from `name`.
    pub fn field_with<T: RosField>(
        mut self,
        name: &str,
        modify: impl FnOnce(FieldType) -> FieldType,
    ) -> Self {
        T::referenced_types(&mut self.referenced);
        self.push_field(name, modify(T::field_type()))
    }

    /// Appends a field with an explicit type (its referenced types must be added separately).
    pub fn push_field(mut self, name: &str, field_type: FieldType) -> Self {
        self.main.fields.push(Field {
            name: name.trim_start_matches("r#").to_owned(),
            r#type: field_type,
            default_value: String::new(),
        });
        self
    }

    /// Sets the `.msg` default value (as rosidl prints it, e.g. `False`, `0`) of the last field.
    pub fn default_value(mut self, value: &str) -> Self {
        if let Some(f) = self.main.fields.last_mut() {
            f.default_value = value.to_owned();
        }
        self
    }

    /// Adds referenced types (for fields added with [`push_field`](Self::push_field)).
    pub fn reference(mut self, description: TypeDescription) -> Self {
        self.referenced.push(description.type_description);
        self.referenced
            .extend(description.referenced_type_descriptions);
        self
    }

    /// Finishes: adds rosidl's `uint8 structure_needs_at_least_one_member` to a struct without
    /// fields, and sorts the referenced types by name without duplicates.
    pub fn build(mut self) -> TypeDescription {
        if self.main.fields.is_empty() {
            self = self.field::<u8>(EMPTY_STRUCTURE_MEMBER);
        }
        TypeDescription {
            type_description: self.main,
            referenced_type_descriptions: sort_dedup(self.referenced),
        }
    }
}

/// Sorts by `type_name` (Python `sorted` on `str` = byte order of UTF-8) and drops repeats.
fn sort_dedup(mut v: Vec<IndividualTypeDescription>) -> Vec<IndividualTypeDescription> {
    v.sort_by(|a, b| a.type_name.cmp(&b.type_name));
    v.dedup_by(|a, b| a.type_name == b.type_name);
    v
}

/// Suffix of a service's request message (`SERVICE_REQUEST_MESSAGE_SUFFIX`).
pub const REQUEST_SUFFIX: &str = "_Request";
/// Suffix of a service's response message.
pub const RESPONSE_SUFFIX: &str = "_Response";
/// Suffix of a service's event message.
pub const EVENT_SUFFIX: &str = "_Event";
/// Type name of the event info message every service event carries.
pub const SERVICE_EVENT_INFO: &str = "service_msgs/msg/ServiceEventInfo";

/// The `<service>_Event` message: `ServiceEventInfo info; Request[<=1] request;
/// Response[<=1] response` (rosidl_parser `definition.py` `Service.__init__`).
pub fn service_event_description(
    service_type_name: &str,
    request: &TypeDescription,
    response: &TypeDescription,
) -> TypeDescription {
    let nested_seq1 = |name: &str| FieldType::nested(name).bounded_sequence_of_nested(1);
    DescriptionBuilder::new(&format!("{service_type_name}{EVENT_SUFFIX}"))
        .field::<crate::service_msgs::msg::ServiceEventInfo>("info")
        .push_field("request", nested_seq1(&request.type_description.type_name))
        .push_field(
            "response",
            nested_seq1(&response.type_description.type_name),
        )
        .reference(request.clone())
        .reference(response.clone())
        .build()
}

/// The service type itself: fields `request_message`, `response_message`, `event_message`
/// (rosidl_generator_type_description `add_srv`), referencing all three and what they reference.
pub fn service_description(
    service_type_name: &str,
    request: &TypeDescription,
    response: &TypeDescription,
) -> TypeDescription {
    let event = service_event_description(service_type_name, request, response);
    let nested = |d: &TypeDescription| FieldType::nested(&d.type_description.type_name);
    DescriptionBuilder::new(service_type_name)
        .push_field("request_message", nested(request))
        .push_field("response_message", nested(response))
        .push_field("event_message", nested(&event))
        .reference(request.clone())
        .reference(response.clone())
        .reference(event)
        .build()
}

/// An action type itself: one nested field per part (`goal`, `result`, `feedback`,
/// `send_goal_service`, `get_result_service`, `feedback_message`; rosidl_generator_type_description
/// `add_action`), referencing them and what they reference.
pub fn action_description(
    action_type_name: &str,
    parts: &[(&str, TypeDescription)],
) -> TypeDescription {
    let mut b = DescriptionBuilder::new(action_type_name);
    for (name, d) in parts {
        b = b
            .push_field(name, FieldType::nested(&d.type_description.type_name))
            .reference(d.clone());
    }
    b.build()
}

impl FieldType {
    /// A nested type as a bounded sequence `T[<=n]`.
    fn bounded_sequence_of_nested(mut self, n: u64) -> Self {
        self.type_id = Self::FIELD_TYPE_NESTED_TYPE_BOUNDED_SEQUENCE;
        self.capacity = n;
        self
    }
}
