//! Cyclone DDS domain configuration the way rmw_cyclonedds_cpp (Jazzy) builds it.
//!
//! `rmw_node.cpp`, `check_create_domain`: from rcl's discovery options
//! (`ROS_AUTOMATIC_DISCOVERY_RANGE`, `ROS_STATIC_PEERS`) it builds one XML fragment, followed by
//! a comma and then the value of `CYCLONEDDS_URI`, so that the user's configuration is applied
//! after (and can override) ours. [`discovery_config`] is that fragment, byte for byte;
//! [`domain_config`] appends the `CYCLONEDDS_URI` part.

/// rcl's automatic discovery range (`ROS_AUTOMATIC_DISCOVERY_RANGE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscoveryRange {
    /// `SYSTEM_DEFAULT`: leave Cyclone's discovery settings alone (static peers ignored).
    SystemDefault,
    /// `SUBNET` (rcl's default): multicast discovery plus the static peers.
    Subnet,
    /// `LOCALHOST`: no multicast; `localhost` and the static peers as unicast peers.
    Localhost,
    /// `OFF`: no multicast, and a per-process domain tag so that nothing is discovered.
    Off,
}

impl DiscoveryRange {
    /// Parses a `ROS_AUTOMATIC_DISCOVERY_RANGE` value as rcl does (case-sensitive; empty or
    /// unset means `SUBNET`); `None` for anything else.
    pub fn from_env_value(value: Option<&str>) -> Option<Self> {
        match value.unwrap_or("") {
            "" | "SUBNET" => Some(Self::Subnet),
            "SYSTEM_DEFAULT" => Some(Self::SystemDefault),
            "LOCALHOST" => Some(Self::Localhost),
            "OFF" => Some(Self::Off),
            _ => None,
        }
    }
}

/// The discovery fragment rmw_cyclonedds builds for `range` and `static_peers`, ending in a
/// comma, or the empty string (SYSTEM_DEFAULT). `pid` goes into the OFF range's domain tag
/// (`ros_discovery_off_<pid>`). Peer addresses are inserted verbatim, as rmw_cyclonedds does.
pub fn discovery_config(range: DiscoveryRange, static_peers: &[String], pid: u32) -> String {
    let (add_localhost, add_static_peers, disable_multicast) = match range {
        DiscoveryRange::Subnet => (false, true, false),
        DiscoveryRange::SystemDefault => (false, false, false),
        DiscoveryRange::Localhost => (true, true, true),
        DiscoveryRange::Off => (false, false, true),
    };
    let mut config = String::new();
    if !(add_localhost || add_static_peers || disable_multicast) {
        return config;
    }
    config.push_str("<CycloneDDS><Domain>");
    if disable_multicast {
        config.push_str("<General><AllowMulticast>false</AllowMulticast></General>");
    }
    let discovery_off = disable_multicast && !add_localhost && !add_static_peers;
    if discovery_off {
        config.push_str("<Discovery><ParticipantIndex>none</ParticipantIndex>");
        config.push_str(&format!("<Tag>ros_discovery_off_{pid}</Tag>"));
    } else {
        config.push_str("<Discovery><ParticipantIndex>auto</ParticipantIndex>");
        config.push_str("<MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>");
    }
    if (add_static_peers && !static_peers.is_empty()) || add_localhost {
        config.push_str("<Peers>");
        if add_localhost {
            config.push_str("<Peer address=\"localhost\"/>");
        }
        // rmw_cyclonedds loops over all static peers here; with `add_static_peers` false
        // (OFF, SYSTEM_DEFAULT) this block is only reached for LOCALHOST, where it is true.
        for peer in static_peers {
            config.push_str("<Peer address=\"");
            config.push_str(peer);
            config.push_str("\"/>");
        }
        config.push_str("</Peers>");
    }
    config.push_str("</Discovery></Domain></CycloneDDS>,");
    config
}

/// The whole configuration string for `dds_create_domain`: [`discovery_config`] followed by
/// `cyclonedds_uri` (the value of `CYCLONEDDS_URI`, if set).
pub fn domain_config(
    range: DiscoveryRange,
    static_peers: &[String],
    pid: u32,
    cyclonedds_uri: Option<&str>,
) -> String {
    let mut config = discovery_config(range, static_peers, pid);
    config.push_str(cyclonedds_uri.unwrap_or(""));
    config
}

/// [`domain_config`] with this process's id and the `CYCLONEDDS_URI` environment variable.
pub fn domain_config_from_env(range: DiscoveryRange, static_peers: &[String]) -> String {
    let uri = std::env::var("CYCLONEDDS_URI").ok();
    domain_config(range, static_peers, std::process::id(), uri.as_deref())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peers(p: &[&str]) -> Vec<String> {
        p.iter().map(|s| (*s).to_owned()).collect()
    }

    const AUTO: &str = "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>";

    #[test]
    fn system_default_adds_nothing_and_ignores_peers() {
        assert_eq!(
            discovery_config(DiscoveryRange::SystemDefault, &peers(&["10.0.0.1"]), 7),
            ""
        );
        assert_eq!(
            domain_config(DiscoveryRange::SystemDefault, &[], 7, Some("file:///x.xml")),
            "file:///x.xml"
        );
    }

    #[test]
    fn subnet_without_and_with_peers() {
        assert_eq!(
            discovery_config(DiscoveryRange::Subnet, &[], 7),
            format!("<CycloneDDS><Domain>{AUTO}</Discovery></Domain></CycloneDDS>,")
        );
        assert_eq!(
            discovery_config(DiscoveryRange::Subnet, &peers(&["10.0.0.1", "host.example"]), 7),
            format!(
                "<CycloneDDS><Domain>{AUTO}<Peers><Peer address=\"10.0.0.1\"/><Peer address=\"host.example\"/></Peers>\
                 </Discovery></Domain></CycloneDDS>,"
            )
        );
    }

    #[test]
    fn localhost_disables_multicast_and_adds_localhost_first() {
        assert_eq!(
            discovery_config(DiscoveryRange::Localhost, &peers(&["192.168.1.2"]), 7),
            format!(
                "<CycloneDDS><Domain><General><AllowMulticast>false</AllowMulticast></General>{AUTO}\
                 <Peers><Peer address=\"localhost\"/><Peer address=\"192.168.1.2\"/></Peers>\
                 </Discovery></Domain></CycloneDDS>,"
            )
        );
    }

    #[test]
    fn off_uses_the_pid_tag_and_ignores_peers() {
        assert_eq!(
            discovery_config(DiscoveryRange::Off, &peers(&["10.0.0.1"]), 4242),
            "<CycloneDDS><Domain><General><AllowMulticast>false</AllowMulticast></General>\
             <Discovery><ParticipantIndex>none</ParticipantIndex><Tag>ros_discovery_off_4242</Tag>\
             </Discovery></Domain></CycloneDDS>,"
        );
    }

    #[test]
    fn cyclonedds_uri_comes_last() {
        let c = domain_config(DiscoveryRange::Localhost, &[], 1, Some("<CycloneDDS/>"));
        assert!(c.starts_with("<CycloneDDS><Domain><General><AllowMulticast>false"));
        assert!(c.ends_with("</CycloneDDS>,<CycloneDDS/>"));
        assert!(domain_config(DiscoveryRange::Subnet, &[], 1, None).ends_with("</CycloneDDS>,"));
    }

    #[test]
    fn range_from_env_value() {
        assert_eq!(
            DiscoveryRange::from_env_value(None),
            Some(DiscoveryRange::Subnet)
        );
        assert_eq!(
            DiscoveryRange::from_env_value(Some("")),
            Some(DiscoveryRange::Subnet)
        );
        assert_eq!(
            DiscoveryRange::from_env_value(Some("LOCALHOST")),
            Some(DiscoveryRange::Localhost)
        );
        assert_eq!(
            DiscoveryRange::from_env_value(Some("OFF")),
            Some(DiscoveryRange::Off)
        );
        assert_eq!(
            DiscoveryRange::from_env_value(Some("SYSTEM_DEFAULT")),
            Some(DiscoveryRange::SystemDefault)
        );
        assert_eq!(DiscoveryRange::from_env_value(Some("localhost")), None);
    }
}
