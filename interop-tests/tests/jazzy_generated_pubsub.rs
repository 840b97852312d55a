//! Generated types on a live graph with a real rclpy node: for a few types (arrays, bounded
//! sequences, wide strings, an image, a pose with covariance), we publish the message rclpy's
//! filler makes (decoded from rclpy's own bytes), an rclpy echo takes it, finds it equal to its
//! own, and publishes it back; we take the echo and find it equal to what we sent. RELIABLE,
//! TRANSIENT_LOCAL, depth 1 on both sides, so nothing depends on who matches first.

#[cfg(jazzy_interfaces)]
mod live {
    use std::time::{Duration, Instant};

    use horus_ros_msgs::{from_cdr, Message};
    use horus_ros_rmw::node::Node;
    use horus_ros_rmw::qos::Qos;
    use horus_ros_rmw::Context;
    use interop_tests::jazzy::*;
    use interop_tests::peers::cdr::{ask, from_hex};
    use interop_tests::peers::RclpyPeer;
    use serde_json::{json, Value};

    const DOMAIN: u32 = 57;
    const LIMIT: Duration = Duration::from_secs(30);

    fn qos() -> Qos {
        Qos::default().reliable().transient_local().keep_last(1)
    }

    /// Publishes rclpy's filled `T` on `/gen/in_<i>` and returns a check of the echo on
    /// `/gen/out_<i>`.
    fn send<T: Message + PartialEq>(
        node: &Node,
        i: usize,
        made: &Value,
    ) -> impl FnOnce() -> Result<(), String> {
        let bytes = from_hex(made[T::TYPE_NAME]["filled"].as_str().expect("filled")).expect("hex");
        let value: T = from_cdr(&bytes).expect("rclpy's bytes decode");
        let publisher = node
            .create_publisher::<T>(&format!("/gen/in_{i}"), &qos())
            .expect("publisher");
        let mut subscription = node
            .create_subscription::<T>(&format!("/gen/out_{i}"), &qos())
            .expect("subscription");
        publisher.publish(value.clone()).expect("publish");
        move || {
            let _publisher = publisher;
            let deadline = Instant::now() + LIMIT;
            loop {
                if let Some(echo) = subscription.try_take().map_err(|e| e.to_string())? {
                    return if echo == value {
                        Ok(())
                    } else {
                        Err(format!("{}: the echo differs: {echo:?}", T::TYPE_NAME))
                    };
                }
                let left = deadline.saturating_duration_since(Instant::now());
                if left.is_zero() || !subscription.wait(left) {
                    return Err(format!("{}: no echo within {LIMIT:?}", T::TYPE_NAME));
                }
            }
        }
    }

    #[test]
    fn rclpy_echoes_generated_messages_unchanged() {
        let names = [
            <test_msgs::msg::Arrays as Message>::TYPE_NAME,
            <test_msgs::msg::BoundedSequences as Message>::TYPE_NAME,
            <test_msgs::msg::WStrings as Message>::TYPE_NAME,
            <sensor_msgs::msg::Image as Message>::TYPE_NAME,
            <geometry_msgs::msg::PoseWithCovarianceStamped as Message>::TYPE_NAME,
        ];
        let made = ask(&json!({ "make": names })).unwrap_or_else(|e| panic!("{e}"));
        let context = Context::builder()
            .domain_id(DOMAIN)
            .build()
            .expect("context");
        let node = context.create_node("generated_types", "/").expect("node");
        let checks: Vec<Box<dyn FnOnce() -> Result<(), String>>> = vec![
            Box::new(send::<test_msgs::msg::Arrays>(&node, 0, &made)),
            Box::new(send::<test_msgs::msg::BoundedSequences>(&node, 1, &made)),
            Box::new(send::<test_msgs::msg::WStrings>(&node, 2, &made)),
            Box::new(send::<sensor_msgs::msg::Image>(&node, 3, &made)),
            Box::new(send::<geometry_msgs::msg::PoseWithCovarianceStamped>(
                &node, 4, &made,
            )),
        ];
        let echoes: Vec<Value> = names
            .iter()
            .enumerate()
            .map(|(i, t)| json!({"type": t, "in": format!("/gen/in_{i}"), "out": format!("/gen/out_{i}")}))
            .collect();
        let mut peer = RclpyPeer::start(&json!({
            "domain": DOMAIN, "namespace": "/", "name": "echo", "echoes": echoes,
        }))
        .unwrap_or_else(|e| panic!("{e}"));
        peer.ready(LIMIT).unwrap_or_else(|e| panic!("{e}"));
        let echoed: Vec<Value> = peer
            .wait_for(LIMIT, "every message taken by the rclpy echo", |lines| {
                let echoed: Vec<Value> = lines
                    .iter()
                    .filter_map(|l| l.get("echoed").cloned())
                    .collect();
                (echoed.len() >= names.len()).then_some(echoed)
            })
            .unwrap_or_else(|e| panic!("{e}\n{}", peer.output()));
        for e in &echoed {
            assert_eq!(
                e["equal"], true,
                "rclpy took another message than it made: {e}"
            );
        }
        let failures: Vec<String> = checks
            .into_iter()
            .filter_map(|check| check().err())
            .collect();
        assert!(failures.is_empty(), "{failures:#?}\n{}", peer.output());
        assert_eq!(peer.finish(LIMIT), Ok(Some(0)), "{}", peer.output());
    }
}

#[cfg(not(jazzy_interfaces))]
#[test]
fn rclpy_echoes_generated_messages_unchanged() {
    interop_tests::require_jazzy_interfaces();
}
