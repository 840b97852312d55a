//! The [`Message`] and [`Service`] traits: ROS type name, DDS type name, type description and
//! RIHS01 type hash of an interface type.

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use crate::description::{
    action_description, service_description, service_event_description, EVENT_SUFFIX,
};
use crate::rihs::rihs01;
use crate::type_description_interfaces::msg::TypeDescription;
use crate::type_hash::TypeHash;

/// What gives a type's full description: an entry of [`crate::INTERFACES`] and of the `TYPES`
/// table of each generated package.
pub type DescribeFn = fn() -> TypeDescription;

/// A ROS 2 message type (a `.msg`, or the request/response part of a `.srv`).
pub trait Message:
    serde::Serialize + serde::de::DeserializeOwned + Clone + std::fmt::Debug + Send + Sync + 'static
{
    /// ROS type name: `pkg/msg/Name`, or `pkg/srv/Name_Request` / `pkg/srv/Name_Response`.
    const TYPE_NAME: &'static str;

    /// The DDS type name: `pkg::msg::dds_::Name_` (`pkg::srv::dds_::Name_Request_` for a request).
    fn dds_type_name() -> String {
        dds_type_name(Self::TYPE_NAME)
    }

    /// The full type description: this type plus every type it references, sorted by name.
    fn type_description() -> TypeDescription;

    /// The RIHS01 hash of [`type_description`](Self::type_description), computed once per type.
    fn type_hash() -> TypeHash {
        cached_hash(Self::TYPE_NAME, || rihs01(&Self::type_description()))
    }
}

/// A ROS 2 service type (`pkg/srv/Name`).
///
/// Implementing it needs only `Request`, `Response` and `TYPE_NAME`: the service description,
/// including the generic `Name_Event` message, is derived from them.
pub trait Service: Send + Sync + 'static {
    /// The request message (`pkg/srv/Name_Request`).
    type Request: Message;
    /// The response message (`pkg/srv/Name_Response`).
    type Response: Message;
    /// ROS type name: `pkg/srv/Name`.
    const TYPE_NAME: &'static str;

    /// The service type description (fields `request_message`, `response_message`,
    /// `event_message`), as rosidl_generator_type_description builds it.
    fn type_description() -> TypeDescription {
        service_description(
            Self::TYPE_NAME,
            &Self::Request::type_description(),
            &Self::Response::type_description(),
        )
    }

    /// The description of the `pkg/srv/Name_Event` message.
    fn event_type_description() -> TypeDescription {
        service_event_description(
            Self::TYPE_NAME,
            &Self::Request::type_description(),
            &Self::Response::type_description(),
        )
    }

    /// The service's RIHS01 hash (shown as "service type hash"), computed once per type.
    fn type_hash() -> TypeHash {
        cached_hash(Self::TYPE_NAME, || rihs01(&Self::type_description()))
    }

    /// RIHS01 hash of the `pkg/srv/Name_Event` message.
    fn event_type_hash() -> TypeHash {
        let name = format!("{}{EVENT_SUFFIX}", Self::TYPE_NAME);
        cached_hash(&name, || rihs01(&Self::event_type_description()))
    }

    /// DDS type name of the request topic: `pkg::srv::dds_::Name_Request_`.
    fn request_dds_type_name() -> String {
        Self::Request::dds_type_name()
    }

    /// DDS type name of the reply topic: `pkg::srv::dds_::Name_Response_`.
    fn response_dds_type_name() -> String {
        Self::Response::dds_type_name()
    }
}

/// Maps a ROS type name to its DDS name: `pkg/msg/Name` → `pkg::msg::dds_::Name_`
/// (rmw_fastrtps_shared_cpp / rmw_cyclonedds_cpp type-name mangling; `demangle.cpp` reverses it).
pub fn dds_type_name(ros_type_name: &str) -> String {
    match ros_type_name.rsplit_once('/') {
        Some((ns, name)) => format!("{}::dds_::{name}_", ns.replace('/', "::")),
        None => format!("dds_::{ros_type_name}_"),
    }
}

/// Maps a DDS type name back to the ROS one: `pkg::msg::dds_::Name_` → `pkg/msg/Name`.
/// Returns `None` for names not of that form.
pub fn ros_type_name_from_dds(dds_type_name: &str) -> Option<String> {
    let (ns, name) = dds_type_name.split_once("::dds_::")?;
    let name = name.strip_suffix('_')?;
    if ns.is_empty() || name.is_empty() || name.contains("::") {
        return None;
    }
    Some(format!("{}/{name}", ns.replace("::", "/")))
}

/// One hash per type name for the whole process (statics in generic fns are shared between
/// instantiations, hence the map).
fn cached_hash(key: &str, compute: impl FnOnce() -> TypeHash) -> TypeHash {
    static CACHE: OnceLock<Mutex<HashMap<String, TypeHash>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(h) = cache.lock().ok().and_then(|m| m.get(key).copied()) {
        return h;
    }
    let h = compute();
    if let Ok(mut m) = cache.lock() {
        m.insert(key.to_owned(), h);
    }
    h
}

/// A ROS 2 action type (`pkg/action/Name`): goal, result and feedback, and the services and
/// message rcl_action carries them in (rosidl_parser `definition.py` `Action`).
pub trait Action: Send + Sync + 'static {
    /// `pkg/action/Name_Goal`.
    type Goal: Message + Default;
    /// `pkg/action/Name_Result` (a default one is what a server answers for a goal it does not
    /// know, or that ended without a result).
    type Result: Message + Default;
    /// `pkg/action/Name_Feedback`.
    type Feedback: Message + Default;
    /// `pkg/action/Name_SendGoal`: request `goal_id`, `goal`; response `accepted`, `stamp`.
    type SendGoal: Service;
    /// `pkg/action/Name_GetResult`: request `goal_id`; response `status`, `result`.
    type GetResult: Service;
    /// `pkg/action/Name_FeedbackMessage`: `goal_id`, `feedback`.
    type FeedbackMessage: Message;
    /// ROS type name: `pkg/action/Name`.
    const TYPE_NAME: &'static str;

    /// The action type description (fields `goal`, `result`, `feedback`, `send_goal_service`,
    /// `get_result_service`, `feedback_message`), as rosidl_generator_type_description's
    /// `add_action` builds it.
    fn type_description() -> TypeDescription {
        action_description(
            Self::TYPE_NAME,
            &[
                ("goal", Self::Goal::type_description()),
                ("result", Self::Result::type_description()),
                ("feedback", Self::Feedback::type_description()),
                ("send_goal_service", Self::SendGoal::type_description()),
                ("get_result_service", Self::GetResult::type_description()),
                (
                    "feedback_message",
                    Self::FeedbackMessage::type_description(),
                ),
            ],
        )
    }

    /// The action's RIHS01 hash, computed once per type.
    fn type_hash() -> TypeHash {
        cached_hash(Self::TYPE_NAME, || rihs01(&Self::type_description()))
    }

    // The constructors and accessors below reach the named fields of the derived types from
    // generic code, as rclrs's `ActionImpl` does (`rosidl_runtime_rs/src/traits.rs`):
    // `create_goal_request`, `split_goal_request`, `create_goal_response`,
    // `get_goal_response_accepted`, `get_goal_response_stamp`, `create_feedback_message`,
    // `split_feedback_message`, `create_result_request`, `get_result_request_uuid`,
    // `create_result_response`, `split_result_response`. Goal ids are the 16 bytes of a
    // `unique_identifier_msgs/msg/UUID`, stamps a `builtin_interfaces/msg/Time` as
    // `(sec, nanosec)`: plain values, whichever package's generated types the action uses.
    // Written once, over the fields rosidl_parser gives the derived types, by
    // [`action_accessors!`](crate::action_accessors), which every generated action uses.

    /// A `SendGoal` request: `goal_id`, `goal`.
    fn create_goal_request(
        goal_id: [u8; 16],
        goal: Self::Goal,
    ) -> <Self::SendGoal as Service>::Request;

    /// The `goal_id` and `goal` of a `SendGoal` request.
    fn split_goal_request(request: <Self::SendGoal as Service>::Request) -> ([u8; 16], Self::Goal);

    /// The `goal_id` of a `SendGoal` request.
    fn goal_request_goal_id(request: &<Self::SendGoal as Service>::Request) -> [u8; 16];

    /// A `SendGoal` response: `accepted`, `stamp` (`(sec, nanosec)`).
    fn create_goal_response(
        accepted: bool,
        stamp: (i32, u32),
    ) -> <Self::SendGoal as Service>::Response;

    /// The `accepted` of a `SendGoal` response.
    fn goal_response_accepted(response: &<Self::SendGoal as Service>::Response) -> bool;

    /// The `stamp` of a `SendGoal` response, as `(sec, nanosec)`.
    fn goal_response_stamp(response: &<Self::SendGoal as Service>::Response) -> (i32, u32);

    /// A `FeedbackMessage`: `goal_id`, `feedback`.
    fn create_feedback_message(
        goal_id: [u8; 16],
        feedback: Self::Feedback,
    ) -> Self::FeedbackMessage;

    /// The `goal_id` and `feedback` of a `FeedbackMessage`.
    fn split_feedback_message(message: Self::FeedbackMessage) -> ([u8; 16], Self::Feedback);

    /// The `goal_id` of a `FeedbackMessage`.
    fn feedback_message_goal_id(message: &Self::FeedbackMessage) -> [u8; 16];

    /// A `GetResult` request: `goal_id`.
    fn create_result_request(goal_id: [u8; 16]) -> <Self::GetResult as Service>::Request;

    /// The `goal_id` of a `GetResult` request.
    fn result_request_goal_id(request: &<Self::GetResult as Service>::Request) -> [u8; 16];

    /// A `GetResult` response: `status` (an `action_msgs/msg/GoalStatus` `STATUS_*`), `result`.
    fn create_result_response(
        status: i8,
        result: Self::Result,
    ) -> <Self::GetResult as Service>::Response;

    /// The `status` and `result` of a `GetResult` response.
    fn split_result_response(
        response: <Self::GetResult as Service>::Response,
    ) -> (i8, Self::Result);
}

/// The constructors and accessors of an `impl Action` over the derived types rosidl_parser
/// builds (`Name_SendGoal_Request { goal_id, goal }`, `_Response { accepted, stamp }`,
/// `Name_GetResult_Request { goal_id }`, `_Response { status, result }`, `Name_FeedbackMessage
/// { goal_id, feedback }`, each `Default`): what horus-ros-codegen and `action!` write inside
/// every `impl Action`.
#[doc(hidden)]
#[macro_export]
macro_rules! action_accessors {
    () => {
        fn create_goal_request(
            goal_id: [u8; 16],
            goal: Self::Goal,
        ) -> <Self::SendGoal as $crate::Service>::Request {
            let mut request =
                <<Self::SendGoal as $crate::Service>::Request as ::core::default::Default>::default();
            request.goal_id.uuid = goal_id;
            request.goal = goal;
            request
        }

        fn split_goal_request(
            request: <Self::SendGoal as $crate::Service>::Request,
        ) -> ([u8; 16], Self::Goal) {
            (request.goal_id.uuid, request.goal)
        }

        fn goal_request_goal_id(request: &<Self::SendGoal as $crate::Service>::Request) -> [u8; 16] {
            request.goal_id.uuid
        }

        fn create_goal_response(
            accepted: bool,
            stamp: (i32, u32),
        ) -> <Self::SendGoal as $crate::Service>::Response {
            let mut response =
                <<Self::SendGoal as $crate::Service>::Response as ::core::default::Default>::default();
            response.accepted = accepted;
            response.stamp.sec = stamp.0;
            response.stamp.nanosec = stamp.1;
            response
        }

        fn goal_response_accepted(response: &<Self::SendGoal as $crate::Service>::Response) -> bool {
            response.accepted
        }

        fn goal_response_stamp(
            response: &<Self::SendGoal as $crate::Service>::Response,
        ) -> (i32, u32) {
            (response.stamp.sec, response.stamp.nanosec)
        }

        fn create_feedback_message(
            goal_id: [u8; 16],
            feedback: Self::Feedback,
        ) -> Self::FeedbackMessage {
            let mut message = <Self::FeedbackMessage as ::core::default::Default>::default();
            message.goal_id.uuid = goal_id;
            message.feedback = feedback;
            message
        }

        fn split_feedback_message(message: Self::FeedbackMessage) -> ([u8; 16], Self::Feedback) {
            (message.goal_id.uuid, message.feedback)
        }

        fn feedback_message_goal_id(message: &Self::FeedbackMessage) -> [u8; 16] {
            message.goal_id.uuid
        }

        fn create_result_request(goal_id: [u8; 16]) -> <Self::GetResult as $crate::Service>::Request {
            let mut request =
                <<Self::GetResult as $crate::Service>::Request as ::core::default::Default>::default();
            request.goal_id.uuid = goal_id;
            request
        }

        fn result_request_goal_id(request: &<Self::GetResult as $crate::Service>::Request) -> [u8; 16] {
            request.goal_id.uuid
        }

        fn create_result_response(
            status: i8,
            result: Self::Result,
        ) -> <Self::GetResult as $crate::Service>::Response {
            let mut response =
                <<Self::GetResult as $crate::Service>::Response as ::core::default::Default>::default();
            response.status = status;
            response.result = result;
            response
        }

        fn split_result_response(
            response: <Self::GetResult as $crate::Service>::Response,
        ) -> (i8, Self::Result) {
            (response.status, response.result)
        }
    };
}
