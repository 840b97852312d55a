//! Generated types (`interop_tests::jazzy`, from the Jazzy wheels' interface files) put on the
//! wire the bytes rclpy puts there, and read rclpy's: for each type below, rclpy
//! (`rclpy.serialization`, rmw_fastrtps' type support) serializes a default-constructed message
//! and one filled with a value in every field and element; our `Default` encodes to rclpy's
//! default bytes (so the `.msg` defaults are right), rclpy's filled bytes decode into our type
//! and encode back to the same bytes, and rclpy reads our bytes as exactly the messages it made; the dynamic codec
//! (`horus_ros_dynamic`, types known only by description) reads and writes the same bytes.
//! No DDS.
//!
//! "The same bytes" allows what rmw_fastrtps leaves unwritten: alignment padding (whatever was
//! in its buffer: zero in ours, in runs under 8 bytes) and the end of its buffer, which it sizes
//! by an estimate that can exceed what it writes (a `wstring` counts one unit more). The value
//! comparison on rclpy's side covers every byte that carries data.

#[cfg(jazzy_interfaces)]
mod cases {
    use std::collections::BTreeMap;

    use horus_ros_msgs::{from_cdr, to_cdr, Message};
    use horus_ros_services::dynamic::{cdr, Schema};
    use interop_tests::jazzy;
    use interop_tests::peers::cdr::{ask, from_hex, to_hex};
    use serde_json::{json, Value};

    /// What each type must do; returns its name and our encodings (default, filled).
    type Case = fn(&str, &str) -> Result<(Vec<u8>, Vec<u8>), String>;

    fn case<T: Message + Default + PartialEq>(
        default: &str,
        filled: &str,
    ) -> Result<(Vec<u8>, Vec<u8>), String> {
        let name = T::TYPE_NAME;
        let rclpy_default = hex(default);
        let ours_default =
            to_cdr(&T::default()).map_err(|e| format!("{name}: encoding Default: {e}"))?;
        same_bytes(name, "Default", &ours_default, &rclpy_default)?;
        let rclpy_filled = hex(filled);
        let value: T =
            from_cdr(&rclpy_filled).map_err(|e| format!("{name}: decoding rclpy's bytes: {e}"))?;
        let ours_filled = to_cdr(&value).map_err(|e| format!("{name}: encoding: {e}"))?;
        same_bytes(name, "filled", &ours_filled, &rclpy_filled)?;
        let again: T = from_cdr(&ours_filled).map_err(|e| format!("{name}: decoding ours: {e}"))?;
        if again != value {
            return Err(format!("{name}: decoding our bytes gives another value"));
        }
        // The dynamic codec (types known at run time from this description) agrees.
        let schema = Schema::from_description(&T::type_description())
            .map_err(|e| format!("{name}: dynamic schema: {e}"))?;
        let dynamic = cdr::decode(&schema, name, &rclpy_filled[4..], false)
            .map_err(|e| format!("{name}: dynamic decode of rclpy's bytes: {e}"))?;
        let dynamic_bytes = cdr::encode(&schema, name, &dynamic)
            .map_err(|e| format!("{name}: dynamic encode: {e}"))?;
        same_bytes(name, "dynamic", &dynamic_bytes, &ours_filled[4..])?;
        Ok((ours_default, ours_filled))
    }

    /// Ours equal rclpy's but for unwritten padding (see the file's comment).
    fn same_bytes(name: &str, what: &str, ours: &[u8], rclpy: &[u8]) -> Result<(), String> {
        let mut run = 0;
        let mut same = rclpy.len() >= ours.len();
        for (a, b) in ours.iter().zip(rclpy) {
            if a == b {
                run = 0;
            } else if *a == 0 && run < 7 {
                run += 1;
            } else {
                same = false;
            }
        }
        if same {
            Ok(())
        } else {
            Err(format!(
                "{name}: {what}: ours\n  {}\nrclpy\n  {}",
                to_hex(ours),
                to_hex(rclpy)
            ))
        }
    }

    fn hex(s: &str) -> Vec<u8> {
        from_hex(s).unwrap_or_else(|e| panic!("{e}"))
    }

    macro_rules! types {
        ($($t:ty),* $(,)?) => {
            vec![$((<$t as Message>::TYPE_NAME, case::<$t> as Case)),*]
        };
    }

    fn rclpy(request: Value) -> Value {
        ask(&request).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn generated_types_encode_and_decode_as_rclpy() {
        use jazzy::*;
        let cases = types![
            test_msgs::msg::Arrays,
            test_msgs::msg::BasicTypes,
            test_msgs::msg::BoundedPlainSequences,
            test_msgs::msg::BoundedSequences,
            test_msgs::msg::Builtins,
            test_msgs::msg::Constants,
            test_msgs::msg::Defaults,
            test_msgs::msg::Empty,
            test_msgs::msg::MultiNested,
            test_msgs::msg::Nested,
            test_msgs::msg::Strings,
            test_msgs::msg::UnboundedSequences,
            test_msgs::msg::WStrings,
            test_msgs::srv::ArraysRequest,
            test_msgs::srv::ArraysResponse,
            test_msgs::srv::BasicTypesRequest,
            test_msgs::srv::BasicTypesResponse,
            test_msgs::srv::BasicTypesEvent,
            test_msgs::srv::EmptyRequest,
            test_msgs::action::FibonacciGoal,
            test_msgs::action::FibonacciResult,
            test_msgs::action::FibonacciFeedback,
            test_msgs::action::FibonacciSendGoalRequest,
            test_msgs::action::FibonacciSendGoalResponse,
            test_msgs::action::FibonacciGetResultResponse,
            test_msgs::action::FibonacciFeedbackMessage,
            test_msgs::action::NestedMessageGoal,
            test_msgs::action::NestedMessageFeedbackMessage,
            std_msgs::msg::Header,
            geometry_msgs::msg::PoseWithCovarianceStamped,
            geometry_msgs::msg::PolygonStamped,
            sensor_msgs::msg::Image,
            sensor_msgs::msg::CameraInfo,
            sensor_msgs::msg::PointCloud2,
            sensor_msgs::msg::NavSatFix,
            nav_msgs::msg::Odometry,
            nav_msgs::msg::OccupancyGrid,
            visualization_msgs::msg::MarkerArray,
            visualization_msgs::msg::InteractiveMarker,
            diagnostic_msgs::msg::DiagnosticArray,
            trajectory_msgs::msg::JointTrajectory,
            trajectory_msgs::msg::MultiDOFJointTrajectory,
            shape_msgs::msg::SolidPrimitive,
            shape_msgs::msg::Mesh,
            stereo_msgs::msg::DisparityImage,
            actionlib_msgs::msg::GoalStatusArray,
            action_msgs::msg::GoalStatusArray,
            action_msgs::srv::CancelGoalResponse,
            lifecycle_msgs::msg::TransitionEvent,
            rcl_interfaces::msg::ParameterEvent,
            rcl_interfaces::msg::ParameterDescriptor,
            rosgraph_msgs::msg::Clock,
            type_description_interfaces::msg::TypeDescription,
            unique_identifier_msgs::msg::UUID,
            builtin_interfaces::msg::Duration,
        ];
        let names: Vec<&str> = cases.iter().map(|(n, _)| *n).collect();
        let made = rclpy(json!({ "make": names }));
        let mut failures = Vec::new();
        let mut ours = BTreeMap::new();
        for (name, check) in &cases {
            let bytes = &made[*name];
            match check(
                bytes["default"].as_str().expect("default"),
                bytes["filled"].as_str().expect("filled"),
            ) {
                Ok((d, f)) => {
                    ours.insert(*name, (d, f));
                }
                Err(e) => failures.push(e),
            }
        }
        // rclpy reads our bytes as the very messages it made.
        let request: BTreeMap<&str, Value> = ours
            .iter()
            .map(|(n, (d, f))| (*n, json!({ "default": to_hex(d), "filled": to_hex(f) })))
            .collect();
        let answers = rclpy(json!({ "compare": request }));
        for name in request.keys() {
            for which in ["default", "filled"] {
                let answer = &answers[*name][which];
                if answer != &Value::Bool(true) {
                    failures.push(format!("{name}: rclpy reading our {which} bytes: {answer}"));
                }
            }
        }
        assert!(
            failures.is_empty(),
            "{} failures:\n{}",
            failures.len(),
            failures.join("\n\n")
        );
        println!(
            "{} types: default and filled values encode as rclpy's, decode from rclpy's and are read back by rclpy",
            cases.len()
        );
    }
}

#[cfg(not(jazzy_interfaces))]
#[test]
fn generated_types_encode_and_decode_as_rclpy() {
    interop_tests::require_jazzy_interfaces();
}
