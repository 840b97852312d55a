//! [`action!`](crate::action): an action type defined in Rust, the same on the wire and in its
//! RIHS01 hashes as the one rosidl generates from the `.action` file with the same fields.

/// Defines an action type in Rust, as a `.action` file does, with the types rcl_action carries
/// it in (rosidl_parser's `Action`: `Name_SendGoal`, `Name_GetResult`, `Name_FeedbackMessage`).
///
/// ```
/// horus_ros_actions::action! {
///     test_msgs/Fibonacci {
///         goal { order: i32 }
///         result { sequence: Vec<i32> }
///         feedback { sequence: Vec<i32> }
///     }
/// }
///
/// use horus_ros_actions::Action;
/// assert_eq!(Fibonacci::TYPE_NAME, "test_msgs/action/Fibonacci");
/// // The same type as the one generated from test_msgs' Fibonacci.action.
/// assert_eq!(
///     Fibonacci::type_hash(),
///     horus_ros_actions::interfaces::test_msgs::action::Fibonacci::type_hash()
/// );
/// ```
///
/// # Grammar
///
/// ```text
/// action! { Definition* }
///
/// Definition := Attribute* Name '{'
///                   Attribute* 'goal'     '{' Fields '}'
///                   Attribute* 'result'   '{' Fields '}'
///                   Attribute* 'feedback' '{' Fields '}'
///               '}'
/// Name       := Ident                  // package `horus_ros`
///             | Ident '/' Ident        // package / action
///             | Ident '/' 'action' '/' Ident
/// ```
///
/// Fields are written as in `horus_ros_services::service!` (types, bounds, attributes, empty
/// parts, the name rules checked at compile time).
///
/// Generated (all `pub`, where the macro is used): `struct Name` implementing
/// [`Action`](crate::Action) (`TYPE_NAME = "pkg/action/Name"`); the messages `NameGoal`,
/// `NameResult`, `NameFeedback` (`pkg/action/Name_Goal`, …); the services `NameSendGoal`
/// (request `goal_id`, `goal`; response `accepted`, `stamp`) and `NameGetResult` (request
/// `goal_id`; response `status`, `result`) with their request and response messages; and the
/// message `NameFeedbackMessage` (`goal_id`, `feedback`).
#[macro_export]
macro_rules! action {
    () => {};
    ($(#$meta:tt)* $pkg:ident / action / $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::action! { @define [$pkg] [$(#$meta)*] $name { $($body)* } }
        $crate::action! { $($rest)* }
    };
    ($(#$meta:tt)* $pkg:ident / $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::action! { @define [$pkg] [$(#$meta)*] $name { $($body)* } }
        $crate::action! { $($rest)* }
    };
    ($(#$meta:tt)* $name:ident { $($body:tt)* } $($rest:tt)*) => {
        $crate::action! { @define [horus_ros] [$(#$meta)*] $name { $($body)* } }
        $crate::action! { $($rest)* }
    };

    // One definition, package known: the names of every generated type pasted (paste's
    // `[<…>]` becomes the bare identifier).
    (@define [$pkg:ident] [$($meta:tt)*] $name:ident {
        $(#$goal_meta:tt)* goal { $($goal:tt)* }
        $(#$result_meta:tt)* result { $($result:tt)* }
        $(#$feedback_meta:tt)* feedback { $($feedback:tt)* } $(,)?
    }) => {
        $crate::__private::pastey::paste! {
            $crate::action! { @emit [$pkg] [$($meta)*] $name
                [<$name Goal>] [<$name Result>] [<$name Feedback>]
                [<$name SendGoal>] [<$name SendGoalRequest>] [<$name SendGoalResponse>]
                [<$name GetResult>] [<$name GetResultRequest>] [<$name GetResultResponse>]
                [<$name FeedbackMessage>]
                [$(#$goal_meta)*] { $($goal)* }
                [$(#$result_meta)*] { $($result)* }
                [$(#$feedback_meta)*] { $($feedback)* }
            }
        }
    };
    (@define [$pkg:ident] [$($meta:tt)*] $name:ident { $($body:tt)* }) => {
        ::core::compile_error!(::core::concat!(
            "action!: the body of `", ::core::stringify!($name),
            "` must be `goal { … } result { … } feedback { … }`"
        ));
    };

    (@emit [$pkg:ident] [$($meta:tt)*] $name:ident
        $goal:ident $result:ident $feedback:ident
        $send_goal:ident $send_goal_req:ident $send_goal_resp:ident
        $get_result:ident $get_result_req:ident $get_result_resp:ident
        $feedback_message:ident
        [$($goal_meta:tt)*] { $($goal_fields:tt)* }
        [$($result_meta:tt)*] { $($result_fields:tt)* }
        [$($feedback_meta:tt)*] { $($feedback_fields:tt)* }
    ) => {
        $($meta)*
        #[doc = ""]
        #[doc = ::core::concat!(
            "ROS 2 action type `", ::core::stringify!($pkg), "/action/", ::core::stringify!($name), "`."
        )]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $name;

        const _: () = {
            ::core::assert!(
                $crate::__private::names::is_valid_package_name(::core::stringify!($pkg)),
                ::core::concat!(
                    "action!: `", ::core::stringify!($pkg), "` is not a valid ROS 2 package name"
                )
            );
            ::core::assert!(
                $crate::__private::names::is_valid_type_name(::core::stringify!($name)),
                ::core::concat!(
                    "action!: `", ::core::stringify!($name), "` is not a valid ROS 2 action name"
                )
            );
        };

        $crate::__private::service! { @message $goal
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_Goal"]
            ["Goal of the ROS 2 action type `", ::core::stringify!($pkg), "/action/", ::core::stringify!($name), "`"]
            [$($goal_meta)*] { $($goal_fields)* } }
        $crate::__private::service! { @message $result
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_Result"]
            ["Result of the ROS 2 action type `", ::core::stringify!($pkg), "/action/", ::core::stringify!($name), "`"]
            [$($result_meta)*] { $($result_fields)* } }
        $crate::__private::service! { @message $feedback
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_Feedback"]
            ["Feedback of the ROS 2 action type `", ::core::stringify!($pkg), "/action/", ::core::stringify!($name), "`"]
            [$($feedback_meta)*] { $($feedback_fields)* } }

        // rosidl_parser `Action.__init__`: the derived services and feedback message.
        $crate::__private::service! { @message $send_goal_req
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_SendGoal_Request"]
            ["Request of `", ::core::stringify!($name), "`'s send_goal service"]
            [] {
                goal_id: $crate::__private::horus_ros_msgs::unique_identifier_msgs::msg::UUID,
                goal: $goal,
            } }
        $crate::__private::service! { @message $send_goal_resp
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_SendGoal_Response"]
            ["Response of `", ::core::stringify!($name), "`'s send_goal service"]
            [] {
                accepted: bool,
                stamp: $crate::__private::horus_ros_msgs::builtin_interfaces::msg::Time,
            } }
        $crate::__private::service! { @message $get_result_req
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_GetResult_Request"]
            ["Request of `", ::core::stringify!($name), "`'s get_result service"]
            [] {
                goal_id: $crate::__private::horus_ros_msgs::unique_identifier_msgs::msg::UUID,
            } }
        $crate::__private::service! { @message $get_result_resp
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_GetResult_Response"]
            ["Response of `", ::core::stringify!($name), "`'s get_result service"]
            [] {
                status: i8,
                result: $result,
            } }
        $crate::__private::service! { @message $feedback_message
            [::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_FeedbackMessage"]
            ["Feedback message of `", ::core::stringify!($name), "` (goal id and feedback)"]
            [] {
                goal_id: $crate::__private::horus_ros_msgs::unique_identifier_msgs::msg::UUID,
                feedback: $feedback,
            } }

        #[doc = ::core::concat!("The send_goal service of `", ::core::stringify!($name), "`.")]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $send_goal;

        impl $crate::__private::horus_ros_msgs::Service for $send_goal {
            type Request = $send_goal_req;
            type Response = $send_goal_resp;
            const TYPE_NAME: &'static str =
                ::core::concat!(::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_SendGoal");
        }

        #[doc = ::core::concat!("The get_result service of `", ::core::stringify!($name), "`.")]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $get_result;

        impl $crate::__private::horus_ros_msgs::Service for $get_result {
            type Request = $get_result_req;
            type Response = $get_result_resp;
            const TYPE_NAME: &'static str =
                ::core::concat!(::core::stringify!($pkg), "/action/", ::core::stringify!($name), "_GetResult");
        }

        impl $crate::__private::horus_ros_msgs::Action for $name {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;
            type SendGoal = $send_goal;
            type GetResult = $get_result;
            type FeedbackMessage = $feedback_message;
            const TYPE_NAME: &'static str =
                ::core::concat!(::core::stringify!($pkg), "/action/", ::core::stringify!($name));

            $crate::__private::horus_ros_msgs::action_accessors!();
        }
    };

    ($($other:tt)+) => {
        ::core::compile_error!(::core::concat!(
            "action!: expected `pkg/Name { goal { … } result { … } feedback { … } }`, found `",
            ::core::stringify!($($other)+), "`"
        ));
    };
}
