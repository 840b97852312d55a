//! The services guide's complete example: a service that looks up robot joint limits by name.
//!
//! The server and the client live in one program (on the process's default node); the call
//! still goes over DDS, so `ros2 service list` in the same domain shows `/get_joint_limits`
//! (type `horus_ros/srv/GetJointLimits`) while it runs.
//!
//! ```text
//! cargo run -p horus-ros-nodes --example get_joint_limits
//! ```
//!
//! It is the guide's program with the
//! limits written with `std::f64::consts` (clippy rejects the literal `3.14`), and one more call
//! that asks for an unknown joint to show the handler's `Err` arriving as `ServiceFailed`.

use horus::prelude::*;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};

// Define the service
service! {
    GetJointLimits {
        request {
            joint_name: String,
        }
        response {
            min_position: f64,
            max_position: f64,
            max_velocity: f64,
            max_effort: f64,
        }
    }
}

fn main() -> Result<()> {
    // Joint limits database
    let limits: HashMap<String, (f64, f64, f64, f64)> = HashMap::from([
        ("shoulder".into(), (-PI, PI, 2.0, 100.0)),
        ("elbow".into(), (0.0, 2.61, 2.0, 80.0)),
        ("wrist".into(), (-FRAC_PI_2, FRAC_PI_2, 3.0, 40.0)),
    ]);

    // Start server
    let _server = ServiceServerBuilder::<GetJointLimits>::new()
        .on_request(move |req| match limits.get(&req.joint_name) {
            Some(&(min, max, vel, effort)) => Ok(GetJointLimitsResponse {
                min_position: min,
                max_position: max,
                max_velocity: vel,
                max_effort: effort,
            }),
            None => Err(format!("Unknown joint: {}", req.joint_name)),
        })
        .build()?;

    // Client usage
    let mut client = ServiceClient::<GetJointLimits>::new()?;

    let resp = client.call(
        GetJointLimitsRequest {
            joint_name: "elbow".into(),
        },
        Duration::from_secs(1),
    )?;

    println!(
        "Elbow limits: [{:.2}, {:.2}] rad",
        resp.min_position, resp.max_position
    );

    // Beyond the guide: a joint the server does not know. The handler's `Err` comes back at
    // once as `ServiceError::ServiceFailed` (a ROS 2 client would get no reply and time out).
    match client.call(
        GetJointLimitsRequest {
            joint_name: "gripper".into(),
        },
        Duration::from_secs(1),
    ) {
        Ok(resp) => println!("Gripper limits: {resp:?}"),
        Err(ServiceError::ServiceFailed(msg)) => println!("Gripper: the server said: {msg}"),
        Err(e) => return Err(e.into()),
    }

    Ok(())
}
