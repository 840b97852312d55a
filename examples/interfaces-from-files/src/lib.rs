//! Rust types generated from ROS 2 interface files by a build script, in a crate of one's own.
//!
//! `build.rs` runs [`horus_ros_codegen::Builder`] on `interfaces/horus_demo_msgs/` (a package
//! directory: `package.xml`, `msg/Telemetry.msg`, `srv/SetMode.srv`) and on `test_msgs` from the
//! ROS 2 Jazzy wheels; this file includes what it wrote, so that the crate has a module per
//! package:
//!
//! - [`horus_demo_msgs::msg::Telemetry`] (with its constants `Telemetry::MODE_ACTIVE`, …, and its
//!   `.msg` defaults as `Default`), [`horus_demo_msgs::srv::SetMode`] with `SetModeRequest` and
//!   `SetModeResponse`;
//! - `test_msgs::msg::Arrays`, `test_msgs::srv::BasicTypes`, … (when the wheels were found).
//!
//! Each type implements `horus_ros_msgs::Message` (its ROS name and RIHS01 hash, as Jazzy's), and
//! a service `horus_ros_msgs::Service`, so they go wherever horus-ros takes a message or a
//! service: publishers and subscriptions, service servers and clients, HORUS topics.
//!
//! The binaries: `telemetry_node` and `telemetry_monitor` talk to each other with the example's
//! own types; `test_msgs_node` talks to rclpy with test_msgs. The values they send are made here
//! ([`telemetry`], [`arrays`], [`basic_types_request`]) so that the receiving side and the tests
//! can check them.

/// The generated packages (`<OUT_DIR>/interfaces.rs`).
#[allow(missing_docs, clippy::all)]
mod interfaces {
    include!(concat!(env!("OUT_DIR"), "/interfaces.rs"));
}

pub use interfaces::*;

use horus_demo_msgs::msg::Telemetry;
use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_msgs::std_msgs::msg::Header;

/// Whether `test_msgs` was generated (found in `AMENT_PREFIX_PATH` or the venv of
/// `HORUS_ROS_INTEROP_PYTHON` when the crate was built).
pub const HAS_TEST_MSGS: bool = !cfg!(no_test_msgs);

/// Why the program cannot talk to rclpy, when test_msgs was not generated.
pub const NO_TEST_MSGS: &str = "this build has no test_msgs: build again with AMENT_PREFIX_PATH \
     naming a ROS 2 install, or HORUS_ROS_INTEROP_PYTHON naming the Python of the venv that \
     scripts/setup makes (<venv>/bin/python)";

/// The `sequence`-th telemetry of robot `robot`, with `cells` battery cells (more than
/// [`Telemetry::MAX_CELLS`] does not encode). Every field has a value that follows from these,
/// so that the receiver can check what it got; [`Telemetry::default`] gives the rest.
pub fn telemetry(robot: &str, sequence: u64, cells: usize) -> Telemetry {
    let step = sequence as f64;
    Telemetry {
        header: Header {
            stamp: Time {
                sec: 1_700_000_000 + (sequence / 10) as i32,
                nanosec: (sequence % 10) as u32 * 100_000_000,
            },
            frame_id: Telemetry::FRAME_ID.to_owned(),
        },
        robot_name: robot.to_owned(),
        sequence,
        speed: 0.5,
        odometer: 0.05 * step,
        // A diagonal covariance, with a correlation between x and y.
        pose_covariance: [0.01, 0.002, 0.0, 0.002, 0.01, 0.0, 0.0, 0.0, 0.05],
        cell_voltages: (0..cells).map(|i| 4.1 - 0.01 * i as f32).collect(),
        warnings: if sequence.is_multiple_of(2) {
            vec!["left wheel slipping".to_owned()]
        } else {
            Vec::new()
        },
        ..Telemetry::default()
    }
}

/// The mode's name, for logs.
pub fn mode_name(mode: u8) -> &'static str {
    match mode {
        Telemetry::MODE_IDLE => "idle",
        Telemetry::MODE_ACTIVE => "active",
        Telemetry::MODE_DOCKED => "docked",
        _ => "unknown",
    }
}

#[cfg(not(no_test_msgs))]
mod with_test_msgs {
    use horus_ros_msgs::Byte;

    use crate::test_msgs::msg::{Arrays, BasicTypes, Defaults};
    use crate::test_msgs::srv::BasicTypesRequest;

    /// A `test_msgs/msg/BasicTypes` with every field at an edge of its type but
    /// `int64_value`, `i64::MIN + k`.
    pub fn basic_types(k: u64) -> BasicTypes {
        BasicTypes {
            bool_value: true,
            byte_value: Byte(0xa5),
            char_value: b'Z',
            float32_value: 1.125,
            float64_value: -2.25e300,
            int8_value: i8::MIN,
            uint8_value: u8::MAX,
            int16_value: i16::MIN,
            uint16_value: u16::MAX,
            int32_value: i32::MIN,
            uint32_value: u32::MAX,
            int64_value: i64::MIN.wrapping_add_unsigned(k),
            uint64_value: u64::MAX,
        }
    }

    /// The `n`-th `test_msgs/msg/Arrays` that `test_msgs_node` publishes: every fixed array
    /// filled (the `*_default` ones keep their `.msg` defaults), `n` in `alignment_check`.
    pub fn arrays(n: u64) -> Arrays {
        Arrays {
            bool_values: [true, false, true],
            byte_values: [Byte(0), Byte(0x7f), Byte(0xff)],
            char_values: [b'h', b'r', b's'],
            float32_values: [1.5, -0.25, f32::MAX],
            float64_values: [std::f64::consts::PI, -1e-300, f64::MIN],
            int8_values: [i8::MIN, 0, i8::MAX],
            uint8_values: [0, 1, u8::MAX],
            int16_values: [i16::MIN, -1, i16::MAX],
            uint16_values: [0, 2, u16::MAX],
            int32_values: [i32::MIN, 3, i32::MAX],
            uint32_values: [0, 4, u32::MAX],
            int64_values: [i64::MIN, 5, i64::MAX],
            uint64_values: [0, 6, u64::MAX],
            string_values: ["horus".into(), String::new(), "ros ↔ rclpy".into()],
            basic_types_values: [basic_types(n), basic_types(n + 1), basic_types(n + 2)],
            defaults_values: [
                Defaults::default(),
                Defaults::default(),
                Defaults::default(),
            ],
            alignment_check: i32::try_from(n).unwrap_or(i32::MAX),
            ..Arrays::default()
        }
    }

    /// The request that rclpy sends to `test_msgs_node` in the test: every basic type.
    pub fn basic_types_request() -> BasicTypesRequest {
        let b = basic_types(7);
        BasicTypesRequest {
            bool_value: b.bool_value,
            byte_value: b.byte_value,
            char_value: b.char_value,
            float32_value: b.float32_value,
            float64_value: b.float64_value,
            int8_value: b.int8_value,
            uint8_value: b.uint8_value,
            int16_value: b.int16_value,
            uint16_value: b.uint16_value,
            int32_value: b.int32_value,
            uint32_value: b.uint32_value,
            int64_value: b.int64_value,
            uint64_value: b.uint64_value,
            string_value: "horus ↔ rclpy".to_owned(),
        }
    }
}

#[cfg(not(no_test_msgs))]
pub use with_test_msgs::{arrays, basic_types, basic_types_request};
