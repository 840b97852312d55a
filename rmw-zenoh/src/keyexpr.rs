//! Data key expressions (rmw_zenoh_cpp 0.2.10 `src/detail/liveliness_utils.cpp`
//! `topic_keyexpr`, `docs/design.md` "Topic and Service name mapping to Zenoh key
//! expressions"; wire facts §3): `<domain>/<name without its leading '/'>/<type>/<type_hash>`,
//! the name keeping its slashes (`0/robot1/chatter/…`).
//!
//! A service's key is its name with the service's DDS type name (`pkg::srv::dds_::Name_`) and
//! the service type's hash (`service_key`); a plain DDS topic name (no `rt/` prefix, as with
//! `avoid_ros_namespace_conventions`) is keyed as it is.

use horus_ros_msgs::TypeHash;
use zenoh::query::QueryTarget;

use horus_ros_rmw_contract::names::{
    ROS_SERVICE_REQUESTER_PREFIX, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX, SERVICE_REQUEST_SUFFIX,
};

/// The service of a request or reply endpoint: its ROS name (`/add_two_ints`) and the DDS type
/// name of the service (`pkg::srv::dds_::Name_`), from the endpoint's DDS topic
/// (`rq/add_two_intsRequest`, `rr/add_two_intsReply`) and type
/// (`pkg::srv::dds_::Name_Request_`, `…_Response_`); `None` for other endpoints.
pub(crate) fn service_of(dds_topic_name: &str, dds_type_name: &str) -> Option<(String, String)> {
    let (prefix, suffix, type_suffix) = if dds_topic_name.starts_with(ROS_SERVICE_REQUESTER_PREFIX)
    {
        (
            ROS_SERVICE_REQUESTER_PREFIX,
            SERVICE_REQUEST_SUFFIX,
            "_Request_",
        )
    } else {
        (
            ROS_SERVICE_RESPONSE_PREFIX,
            SERVICE_REPLY_SUFFIX,
            "_Response_",
        )
    };
    let name = dds_topic_name
        .strip_prefix(prefix)?
        .strip_prefix('/')?
        .strip_suffix(suffix)?;
    let base = dds_type_name.strip_suffix(type_suffix)?;
    (!name.is_empty()).then(|| (format!("/{name}"), format!("{base}_")))
}

/// The key of the service `name` (`/add_two_ints`) of the DDS service type `type_name` with
/// the service type's hash (wire facts §3).
pub(crate) fn service_key(
    domain: u32,
    name: &str,
    type_name: &str,
    type_hash: &TypeHash,
) -> String {
    format!(
        "{domain}/{}/{type_name}/{type_hash}",
        name.trim_start_matches('/')
    )
}

/// What a client queries: a key and a target.
pub(crate) struct ServiceQuery {
    /// The key expression.
    pub(crate) key: String,
    /// Which queryables answer.
    pub(crate) target: QueryTarget,
}

/// What a client of the service `name` of `type_name` queries: the service's key with target
/// `ALL_COMPLETE` (rmw_client_data.cpp), or — for a client that does not know its service
/// type's hash ([`TypeHash::ZERO`]: one built from DDS type names only) — the key with `*` for
/// the hash and target `ALL` (no queryable is complete for a wildcard), which every server of
/// that name and type answers, each on its own key.
pub(crate) fn service_query(
    domain: u32,
    name: &str,
    type_name: &str,
    type_hash: &TypeHash,
) -> ServiceQuery {
    if *type_hash == TypeHash::ZERO {
        ServiceQuery {
            key: format!("{domain}/{}/{type_name}/*", name.trim_start_matches('/')),
            target: QueryTarget::All,
        }
    } else {
        ServiceQuery {
            key: service_key(domain, name, type_name, type_hash),
            target: QueryTarget::AllComplete,
        }
    }
}

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
        None => format!("{domain}/{dds_topic_name}/{type_name}/{type_hash}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_client_without_the_service_hash_queries_every_hash() {
        let ty = "example_interfaces::srv::dds_::AddTwoInts_";
        let query = service_query(7, "/add_two_ints", ty, &TypeHash::ZERO);
        assert_eq!(
            (query.key.as_str(), query.target),
            (
                "7/add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/*",
                QueryTarget::All
            )
        );
        let hash = TypeHash::parse(
            "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a",
        )
        .expect("hash");
        let query = service_query(7, "/add_two_ints", ty, &hash);
        assert_eq!(
            (query.key, query.target),
            (
                service_key(7, "/add_two_ints", ty, &hash),
                QueryTarget::AllComplete
            )
        );
    }

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
        assert!(data_key(0, "plain", "T", &hash).starts_with("0/plain/T/"));
        let service = "example_interfaces::srv::dds_::AddTwoInts_";
        let (name, ty) = service_of(
            "rq/add_two_intsRequest",
            "example_interfaces::srv::dds_::AddTwoInts_Request_",
        )
        .expect("request");
        assert_eq!((name.as_str(), ty.as_str()), ("/add_two_ints", service));
        let (name, ty) = service_of(
            "rr/ns/add_two_intsReply",
            "example_interfaces::srv::dds_::AddTwoInts_Response_",
        )
        .expect("reply");
        assert_eq!((name.as_str(), ty.as_str()), ("/ns/add_two_ints", service));
        assert_eq!(service_of("rt/chatter", "T_"), None);
        let hash = TypeHash::parse(
            "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a",
        )
        .expect("hash");
        assert_eq!(
            service_key(0, "/add_two_ints", service, &hash),
            "0/add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"
        );

        assert_eq!(ros_topic_of("rt/a/b").as_deref(), Some("/a/b"));
        assert_eq!(ros_topic_of("rt/"), None);
        assert_eq!(ros_topic_of("ros_discovery_info"), None);
    }
}
