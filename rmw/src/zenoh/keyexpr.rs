//! Data key expressions (rmw_zenoh_cpp 0.2.10 `src/detail/liveliness_utils.cpp`
//! `topic_keyexpr`, `docs/design.md` "Topic and Service name mapping to Zenoh key
//! expressions"; wire facts §3): `<domain>/<name without its leading '/'>/<type>/<type_hash>`,
//! the name keeping its slashes (`0/robot1/chatter/…`).
//!
//! Endpoints that are not topics (the `rq/`/`rr/` request and reply topics of the DDS service
//! conventions, or plain DDS topic names) are not rmw_zenoh's: until services are queryables
//! (milestone 2) they travel between horus-ros processes under `<domain>/@horus/<DDS topic
//! name>/<type>/<type_hash>`, which no rmw_zenoh key matches (`@horus` is a hermetic chunk).

use horus_ros_msgs::TypeHash;

use crate::names::ROS_TOPIC_PREFIX;

/// The ROS topic name (`/chatter`) of a DDS topic name `rt/chatter`; `None` for other names.
pub(crate) fn ros_topic_of(dds_topic_name: &str) -> Option<String> {
    let rest = dds_topic_name
        .strip_prefix(ROS_TOPIC_PREFIX)?
        .strip_prefix('/')?;
    (!rest.is_empty()).then(|| format!("/{rest}"))
}

/// The data key of an endpoint on `dds_topic_name` with this type.
pub(crate) fn data_key(
    domain: u32,
    dds_topic_name: &str,
    type_name: &str,
    type_hash: &TypeHash,
) -> String {
    match ros_topic_of(dds_topic_name) {
        Some(topic) => format!("{domain}/{}/{type_name}/{type_hash}", &topic[1..]),
        None => format!("{domain}/@horus/{dds_topic_name}/{type_name}/{type_hash}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topics_are_keyed_as_rmw_zenoh_keys_them() {
        let hash = TypeHash::parse(
            "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
        )
        .expect("hash");
        assert_eq!(
            data_key(0, "rt/chatter", "std_msgs::msg::dds_::String_", &hash),
            "0/chatter/std_msgs::msg::dds_::String_/RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
        );
        assert!(
            data_key(7, "rt/robot1/chatter", "T", &hash).starts_with("7/robot1/chatter/T/RIHS01_")
        );
        assert!(data_key(0, "rq/add_two_intsRequest", "T", &hash)
            .starts_with("0/@horus/rq/add_two_intsRequest/T/"));
        assert_eq!(ros_topic_of("rt/a/b").as_deref(), Some("/a/b"));
        assert_eq!(ros_topic_of("rt/"), None);
        assert_eq!(ros_topic_of("ros_discovery_info"), None);
    }
}
