//! [`ServiceType`]: a service type known at run time — its request and response descriptions and
//! the schema built from them — with requests filled from YAML or JSON and responses decoded, as
//! [`DynamicServiceClient`](../horus_ros_services/struct.DynamicServiceClient.html) calls with
//! them.

use horus_ros_msgs::description::{REQUEST_SUFFIX, RESPONSE_SUFFIX};
use horus_ros_msgs::{TypeDescription, TypeHash};

use crate::cdr::{DecodeError, EncodeError};
use crate::yaml::FillError;
use crate::{cdr, json, repr, sub_description, yaml, Schema, SchemaError, Value};

/// Why a request could not be made for a [`ServiceType`]: its values do not fill the request
/// type ([`ServiceType::request_from_yaml`], [`ServiceType::request_from_json`]), or the value
/// does not encode ([`ServiceType::encode_request`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RequestError {
    /// The values do not fill the request type.
    #[error(transparent)]
    Fill(#[from] FillError),
    /// The request value does not encode.
    #[error(transparent)]
    Encode(#[from] EncodeError),
}

/// A service type known at run time (`pkg/srv/Name`).
#[derive(Clone, Debug)]
pub struct ServiceType {
    name: String,
    /// `pkg/srv/Name_Request` and `pkg/srv/Name_Response`, made once.
    request_type: String,
    response_type: String,
    schema: Schema,
    request: TypeDescription,
    response: TypeDescription,
    /// The RIHS01 hash of the service type itself (ZERO when the descriptions lack it).
    service_hash: TypeHash,
}

impl ServiceType {
    /// `service_type` from descriptions that contain its request and response types (and what
    /// they use): e.g. what a node's `~/get_type_description` returned.
    pub fn from_descriptions(
        service_type: &str,
        descriptions: &[TypeDescription],
    ) -> Result<Self, SchemaError> {
        let req_name = format!("{service_type}{REQUEST_SUFFIX}");
        let resp_name = format!("{service_type}{RESPONSE_SUFFIX}");
        let find = |name: &str| {
            descriptions
                .iter()
                .find_map(|d| sub_description(d, name).ok())
                .ok_or_else(|| SchemaError::missing(name))
        };
        let request = find(&req_name)?;
        let response = find(&resp_name)?;
        let mut schema = Schema::from_description(&request)?;
        schema.add(&response)?;
        schema.check(&req_name)?;
        schema.check(&resp_name)?;
        let service_hash = descriptions
            .iter()
            .find_map(|d| sub_description(d, service_type).ok())
            .map_or(TypeHash::ZERO, |d| d.compute_type_hash());
        Ok(Self {
            name: service_type.to_owned(),
            request_type: req_name,
            response_type: resp_name,
            schema,
            request,
            response,
            service_hash,
        })
    }

    /// A service type compiled into horus-ros-msgs (`None` for any other).
    pub fn compiled(service_type: &str) -> Option<Self> {
        let description = compiled_description(service_type)?;
        Self::from_descriptions(service_type, &[description]).ok()
    }

    /// The service type's name (`pkg/srv/Name`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The structs of the request and response.
    pub fn schema(&self) -> &Schema {
        &self.schema
    }

    /// The request type's name (`pkg/srv/Name_Request`).
    pub fn request_type(&self) -> &str {
        &self.request_type
    }

    /// The response type's name (`pkg/srv/Name_Response`).
    pub fn response_type(&self) -> &str {
        &self.response_type
    }

    /// The request type's full description.
    pub fn request_description(&self) -> &TypeDescription {
        &self.request
    }

    /// The response type's full description.
    pub fn response_description(&self) -> &TypeDescription {
        &self.response
    }

    /// The RIHS01 hash of the service type itself (`pkg/srv/Name`), which rmw_zenoh's service keys
    /// carry; [`TypeHash::ZERO`] when the descriptions it was made from lack the service's own
    /// (e.g. only its request and response).
    pub fn service_hash(&self) -> TypeHash {
        self.service_hash
    }

    /// The RIHS01 hashes of the request and response types.
    pub fn part_hashes(&self) -> (TypeHash, TypeHash) {
        (
            self.request.compute_type_hash(),
            self.response.compute_type_hash(),
        )
    }

    /// A request filled from ros2cli's YAML (`service call`'s values: `'{a: 1, b: 2}'`).
    pub fn request_from_yaml(&self, text: &str) -> Result<Value, FillError> {
        yaml::fill_from_yaml(&self.schema, &self.request_type, text)
    }

    /// A request filled from a JSON object of its fields (checked as YAML values are).
    pub fn request_from_json(&self, value: &serde_json::Value) -> Result<Value, FillError> {
        json::fill_from_json(&self.schema, &self.request_type, value)
    }

    /// The request's CDR body (little-endian, no encapsulation header).
    pub fn encode_request(&self, request: &Value) -> Result<Vec<u8>, EncodeError> {
        cdr::encode(&self.schema, &self.request_type, request)
    }

    /// A response decoded from its CDR body.
    pub fn decode_response(&self, body: &[u8], big_endian: bool) -> Result<Value, DecodeError> {
        cdr::decode(&self.schema, &self.response_type, body, big_endian)
    }

    /// A response as a JSON object of its fields.
    pub fn response_to_json(&self, response: &Value) -> serde_json::Value {
        json::to_json(&self.schema, &self.response_type, response)
    }

    /// A request as Python's `repr` shows it (what `service call` prints).
    pub fn request_repr(&self, request: &Value) -> String {
        repr::repr(&self.schema, &self.request_type, request)
    }

    /// A response as Python's `repr` shows it.
    pub fn response_repr(&self, response: &Value) -> String {
        repr::repr(&self.schema, &self.response_type, response)
    }
}

/// The description of a service type compiled into horus-ros-msgs.
pub fn compiled_description(service_type: &str) -> Option<TypeDescription> {
    crate::compiled::compiled_type(service_type)
        .filter(|t| t.is_service())
        .map(|t| (t.describe)())
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_msgs::example_interfaces;
    use horus_ros_msgs::Message;

    #[test]
    fn the_service_hash_is_the_service_types_own() {
        use horus_ros_msgs::Service;
        let ty = ServiceType::compiled("example_interfaces/srv/AddTwoInts").expect("compiled");
        assert_eq!(
            ty.service_hash(),
            example_interfaces::srv::AddTwoInts::type_hash()
        );
        let parts_only = ServiceType::from_descriptions(
            "example_interfaces/srv/AddTwoInts",
            &[
                ty.request_description().clone(),
                ty.response_description().clone(),
            ],
        )
        .expect("parts");
        assert_eq!(parts_only.service_hash(), TypeHash::ZERO);
    }

    #[test]
    fn a_compiled_service_type_is_filled_from_yaml_or_json_and_answers_in_json() {
        let ty = ServiceType::compiled("example_interfaces/srv/AddTwoInts").expect("compiled");
        let from_yaml = ty.request_from_yaml("{a: 2, b: 3}").expect("yaml");
        let from_json = ty
            .request_from_json(&serde_json::json!({"a": 2, "b": 3}))
            .expect("json");
        assert_eq!(from_yaml, from_json);
        let body = ty.encode_request(&from_json).expect("encode");
        let compiled =
            horus_ros_msgs::cdr::to_cdr_body(&example_interfaces::srv::AddTwoIntsRequest {
                a: 2,
                b: 3,
            })
            .expect("compiled encode");
        assert_eq!(body, compiled);
        let reply =
            horus_ros_msgs::cdr::to_cdr_body(&example_interfaces::srv::AddTwoIntsResponse {
                sum: 5,
            })
            .expect("compiled encode");
        let response = ty.decode_response(&reply, false).expect("decode");
        assert_eq!(
            ty.response_to_json(&response),
            serde_json::json!({"sum": 5})
        );
        assert_eq!(
            ty.response_repr(&response),
            "example_interfaces.srv.AddTwoInts_Response(sum=5)"
        );
        assert_eq!(
            ty.part_hashes(),
            (
                example_interfaces::srv::AddTwoIntsRequest::type_hash(),
                example_interfaces::srv::AddTwoIntsResponse::type_hash()
            )
        );
    }

    #[test]
    fn bad_values_are_refused_with_the_field_named() {
        let ty = ServiceType::compiled("example_interfaces/srv/AddTwoInts").expect("compiled");
        let e = ty
            .request_from_json(&serde_json::json!({"c": 1}))
            .expect_err("no such field");
        assert!(
            matches!(&e, FillError::NoSuchField { field, .. } if field == "c"),
            "{e}"
        );
        let e = ty
            .request_from_json(&serde_json::json!({"a": "two"}))
            .expect_err("wrong type");
        assert!(
            matches!(&e, FillError::InvalidInteger { field, text } if field == "a" && text == "two"),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "invalid literal for int() with base 10: 'two'"
        );
        let e = ty
            .request_from_json(&serde_json::json!({"a": [1]}))
            .expect_err("wrong type");
        assert_eq!(e.to_string(), "The 'a' field must be of type 'int'");
        assert!(ty.request_from_yaml("{a: [").is_err());
        assert!(ServiceType::compiled("foo/srv/Nope").is_none());
    }

    #[test]
    fn nested_requests_survive_json() {
        let ty = ServiceType::compiled("rcl_interfaces/srv/SetParameters").expect("compiled");
        let json = serde_json::json!({"parameters": [
            {"name": "speed", "value": {"type": 3, "double_value": 1.5}},
            {"name": "names", "value": {"type": 9, "string_array_value": ["a", "b"]}}
        ]});
        let request = ty.request_from_json(&json).expect("json");
        let again = json::to_json(ty.schema(), ty.request_type(), &request);
        assert_eq!(again["parameters"][0]["name"], "speed");
        assert_eq!(again["parameters"][0]["value"]["double_value"], 1.5);
        assert_eq!(
            again["parameters"][1]["value"]["string_array_value"][1],
            "b"
        );
        assert_eq!(ty.request_from_json(&again).expect("round trip"), request);
    }
}
