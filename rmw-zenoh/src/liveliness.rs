//! rmw_zenoh's liveliness tokens: the graph of a Zenoh ROS 2 system (rmw_zenoh_cpp 0.2.10,
//! `src/detail/liveliness_utils.cpp`, `docs/design.md` "Graph cache"; observed on the wire:
//! `shared/docs/rmw-zenoh-jazzy-wire-facts.md` §2).
//!
//! ```text
//! node:   @ros2_lv/<domain>/<zid>/<node_id>/<node_id>/NN/<enclave>/<namespace>/<node_name>
//! entity: @ros2_lv/<domain>/<zid>/<node_id>/<entity_id>/<kind>/<enclave>/<namespace>/<node_name>/<topic>/<type>/<type_hash>/<qos>
//! ```
//!
//! Enclave, namespace and topic are mangled (every `/` becomes `%`, the empty string `%`); the
//! QoS is `qos_to_keyexpr`'s; an entity's GID is the XXH3-128 (seed 0) of the whole key,
//! `low64` then `high64`, both little-endian (`Entity::Entity` in `liveliness_utils.cpp`).

use std::fmt;

use horus_ros_msgs::TypeHash;

use horus_ros_rmw_contract::qos::{
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, Qos, QosDuration, ReliabilityPolicy,
};
use horus_ros_rmw_contract::Gid;

/// The admin prefix of every token (`ADMIN_SPACE` in `liveliness_utils.cpp`); a hermetic chunk
/// (`@…`), so only `@ros2_lv/**` matches it.
pub(crate) const ADMIN_SPACE: &str = "@ros2_lv";

/// rmw_zenoh's default depth (`QoS::default_qos`, `RMW_ZENOH_DEFAULT_HISTORY_DEPTH`): a token
/// leaves the depth empty when it is this.
pub(crate) const DEFAULT_DEPTH: usize = 42;

/// What a token announces (`EntityType` and `entity_to_str` in `liveliness_utils.cpp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum EntityKind {
    /// `NN`: a node.
    Node,
    /// `MP`: a publisher.
    Publisher,
    /// `MS`: a subscription.
    Subscription,
    /// `SS`: a service server.
    Service,
    /// `SC`: a service client.
    Client,
}

impl EntityKind {
    /// The two letters in the token.
    pub(crate) const fn as_str(self) -> &'static str {
        match self {
            Self::Node => "NN",
            Self::Publisher => "MP",
            Self::Subscription => "MS",
            Self::Service => "SS",
            Self::Client => "SC",
        }
    }

    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "NN" => Self::Node,
            "MP" => Self::Publisher,
            "MS" => Self::Subscription,
            "SS" => Self::Service,
            "SC" => Self::Client,
            _ => return None,
        })
    }
}

/// The topic (or service) part of an entity token.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TopicInfo {
    /// The fully qualified ROS name (`/chatter`).
    pub(crate) name: String,
    /// The DDS type name (`std_msgs::msg::dds_::String_`).
    pub(crate) type_name: String,
    /// The RIHS01 hash.
    pub(crate) type_hash: TypeHash,
    /// The QoS as the token tells it.
    pub(crate) qos: Qos,
}

/// One liveliness token, parsed or to be declared.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Token {
    /// The ROS domain.
    pub(crate) domain: u32,
    /// The Zenoh session's id, as Zenoh prints it (lower-case hex, leading zeros dropped).
    pub(crate) zid: String,
    /// The node's id in its session.
    pub(crate) node_id: u64,
    /// The entity's id in its session (the node's own for `NN`).
    pub(crate) entity_id: u64,
    /// What it announces.
    pub(crate) kind: EntityKind,
    /// The security enclave (`/`).
    pub(crate) enclave: String,
    /// The node's namespace (`/`).
    pub(crate) namespace: String,
    /// The node's name.
    pub(crate) node_name: String,
    /// The topic part; `None` for a node.
    pub(crate) topic: Option<TopicInfo>,
}

/// `/` → `%` (`mangle_name` in `liveliness_utils.cpp`); the empty string is `%` there too, since
/// a key expression chunk cannot be empty.
pub(crate) fn mangle(name: &str) -> String {
    if name.is_empty() {
        return "%".to_owned();
    }
    name.replace('/', "%")
}

/// `%` → `/` (`demangle_name`).
pub(crate) fn demangle(name: &str) -> String {
    name.replace('%', "/")
}

impl Token {
    /// The key expression, as `Entity::Entity` joins it.
    pub(crate) fn key(&self) -> String {
        let mut key = format!(
            "{ADMIN_SPACE}/{}/{}/{}/{}/{}/{}/{}/{}",
            self.domain,
            self.zid,
            self.node_id,
            self.entity_id,
            self.kind.as_str(),
            mangle(&self.enclave),
            mangle(&self.namespace),
            self.node_name,
        );
        if let Some(topic) = &self.topic {
            key.push_str(&format!(
                "/{}/{}/{}/{}",
                mangle(&topic.name),
                topic.type_name,
                topic.type_hash,
                qos_to_keyexpr(&topic.qos)
            ));
        }
        key
    }

    /// Parses a token key; why not, if it is malformed.
    pub(crate) fn parse(key: &str) -> Result<Self, TokenError> {
        let parts: Vec<&str> = key.split('/').collect();
        if parts.first() != Some(&ADMIN_SPACE) {
            return Err(TokenError::Prefix);
        }
        let kind = parts
            .get(5)
            .and_then(|k| EntityKind::parse(k))
            .ok_or(TokenError::Kind)?;
        let want = if kind == EntityKind::Node { 9 } else { 13 };
        if parts.len() != want {
            return Err(TokenError::Parts {
                found: parts.len(),
                want,
            });
        }
        let number = |i: usize, what: &'static str| {
            parts[i]
                .parse::<u64>()
                .map_err(|_| TokenError::Number(what))
        };
        let topic = if kind == EntityKind::Node {
            None
        } else {
            Some(TopicInfo {
                name: demangle(parts[9]),
                type_name: parts[10].to_owned(),
                type_hash: parse_type_hash(parts[11])?,
                qos: keyexpr_to_qos(parts[12]).ok_or(TokenError::Qos)?,
            })
        };
        if parts[2].is_empty() || !parts[2].bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(TokenError::Zid);
        }
        Ok(Self {
            domain: parts[1].parse().map_err(|_| TokenError::Number("domain"))?,
            zid: parts[2].to_owned(),
            node_id: number(3, "node id")?,
            entity_id: number(4, "entity id")?,
            kind,
            enclave: demangle(parts[6]),
            namespace: demangle(parts[7]),
            node_name: parts[8].to_owned(),
            topic,
        })
    }

    /// The GID rmw_zenoh gives the entity.
    #[cfg(test)]
    pub(crate) fn gid(&self) -> Gid {
        gid_of_key(&self.key())
    }
}

/// `RIHS01_<64 hex>`, or the unset hash as it prints (`RIHS00_` and 64 zeros: an endpoint whose
/// type has no hash, which a horus-ros raw endpoint may announce).
fn parse_type_hash(s: &str) -> Result<TypeHash, TokenError> {
    if s == TypeHash::ZERO.to_string() {
        return Ok(TypeHash::ZERO);
    }
    TypeHash::parse(s).map_err(|_| TokenError::TypeHash)
}

/// XXH3-128 (seed 0) of `key`: `low64` little-endian, then `high64` little-endian
/// (`liveliness_utils.cpp`: `memcpy(gid_, &keyexpr_gid.low64, 8)`, then `high64`).
pub(crate) fn gid_of_key(key: &str) -> Gid {
    let h = xxhash_rust::xxh3::xxh3_128(key.as_bytes());
    let mut bytes = [0u8; 16];
    bytes[..8].copy_from_slice(&(h as u64).to_le_bytes());
    bytes[8..].copy_from_slice(&((h >> 64) as u64).to_le_bytes());
    Gid::from_bytes(bytes)
}

/// Why a token key could not be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum TokenError {
    /// It is not under `@ros2_lv`.
    #[error("not under {ADMIN_SPACE}")]
    Prefix,
    /// The entity kind is not NN, MP, MS, SS or SC.
    #[error("unknown entity kind")]
    Kind,
    /// Too many or too few chunks for its kind.
    #[error("{found} chunks where {want} were expected")]
    Parts {
        /// Chunks found.
        found: usize,
        /// Chunks expected.
        want: usize,
    },
    /// A number chunk is not a decimal number.
    #[error("bad {0}")]
    Number(&'static str),
    /// The Zenoh id is not hexadecimal.
    #[error("bad zenoh id")]
    Zid,
    /// The type hash is not `RIHS01_<64 hex>`.
    #[error("bad type hash")]
    TypeHash,
    /// The QoS chunk is not `qos_to_keyexpr`'s.
    #[error("bad qos")]
    Qos,
}

/// The rmw enum value of a reliability (`rmw_qos_reliability_policy_e`): 1 RELIABLE,
/// 2 BEST_EFFORT; the defaults (system default, best available) are RELIABLE, as rmw_zenoh
/// resolves them.
fn reliability_value(r: ReliabilityPolicy) -> u8 {
    match r {
        ReliabilityPolicy::BestEffort => 2,
        _ => 1,
    }
}

/// `rmw_qos_durability_policy_e`: 1 TRANSIENT_LOCAL, 2 VOLATILE (the default).
fn durability_value(d: DurabilityPolicy) -> u8 {
    match d {
        DurabilityPolicy::TransientLocal => 1,
        _ => 2,
    }
}

/// `rmw_qos_history_policy_e`: 1 KEEP_LAST (the default), 2 KEEP_ALL.
fn history_value(h: HistoryPolicy) -> u8 {
    match h {
        HistoryPolicy::KeepAll => 2,
        _ => 1,
    }
}

/// `rmw_qos_liveliness_policy_e`: 1 AUTOMATIC (the default), 3 MANUAL_BY_TOPIC.
fn liveliness_value(l: LivelinessPolicy) -> u8 {
    match l {
        LivelinessPolicy::ManualByTopic => 3,
        _ => 1,
    }
}

/// A duration's `sec,nsec`, empty for rmw_zenoh's default (infinite; an unspecified duration
/// means the same).
fn duration_parts(d: QosDuration) -> (String, String) {
    if d.is_default() || d.is_infinite() || d.is_best_available() {
        return (String::new(), String::new());
    }
    let (sec, nsec) = d.to_rmw_time();
    (sec.to_string(), nsec.to_string())
}

/// `qos_to_keyexpr` (`liveliness_utils.cpp`): `rel:dur:hist,depth:dl_s,dl_ns:ls_s,ls_ns:liv,lease_s,lease_ns`,
/// each field empty when it equals rmw_zenoh's default (RELIABLE, VOLATILE, KEEP_LAST, depth
/// 42, infinite deadline, lifespan and lease, AUTOMATIC).
pub(crate) fn qos_to_keyexpr(qos: &Qos) -> String {
    let field = |v: u8, default: u8| {
        if v == default {
            String::new()
        } else {
            v.to_string()
        }
    };
    // The system-default depth (0) is rmw_zenoh's default, 42 (`QoS::best_available_qos`).
    let depth = if qos.depth == 0 || qos.depth == DEFAULT_DEPTH {
        String::new()
    } else {
        qos.depth.to_string()
    };
    let (dl_s, dl_ns) = duration_parts(qos.deadline);
    let (ls_s, ls_ns) = duration_parts(qos.lifespan);
    let (lease_s, lease_ns) = duration_parts(qos.liveliness_lease_duration);
    format!(
        "{}:{}:{},{depth}:{dl_s},{dl_ns}:{ls_s},{ls_ns}:{},{lease_s},{lease_ns}",
        field(reliability_value(qos.reliability), 1),
        field(durability_value(qos.durability), 2),
        field(history_value(qos.history), 1),
        field(liveliness_value(qos.liveliness), 1),
    )
}

/// `keyexpr_to_qos`: the inverse of [`qos_to_keyexpr`]; an empty field is the default.
pub(crate) fn keyexpr_to_qos(s: &str) -> Option<Qos> {
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 6 {
        return None;
    }
    let num = |s: &str| -> Option<Option<u64>> {
        if s.is_empty() {
            Some(None)
        } else {
            s.parse().ok().map(Some)
        }
    };
    let pair = |s: &str| -> Option<(Option<u64>, Option<u64>)> {
        let (a, b) = s.split_once(',')?;
        Some((num(a)?, num(b)?))
    };
    let duration = |s: &str| -> Option<QosDuration> {
        match pair(s)? {
            (None, None) => Some(QosDuration::Infinite),
            (sec, nsec) => Some(QosDuration::from_rmw_time(
                sec.unwrap_or(0),
                nsec.unwrap_or(0),
            )),
        }
    };
    let mut qos = Qos::default_profile();
    qos.reliability = match num(parts[0])? {
        None | Some(1) => ReliabilityPolicy::Reliable,
        Some(2) => ReliabilityPolicy::BestEffort,
        Some(_) => ReliabilityPolicy::Unknown,
    };
    qos.durability = match num(parts[1])? {
        None | Some(2) => DurabilityPolicy::Volatile,
        Some(1) => DurabilityPolicy::TransientLocal,
        Some(_) => DurabilityPolicy::Unknown,
    };
    let (history, depth) = pair(parts[2])?;
    qos.history = match history {
        None | Some(1) => HistoryPolicy::KeepLast,
        Some(2) => HistoryPolicy::KeepAll,
        Some(_) => HistoryPolicy::Unknown,
    };
    qos.depth = match depth {
        None => DEFAULT_DEPTH,
        Some(d) => usize::try_from(d).ok()?,
    };
    qos.deadline = duration(parts[3])?;
    qos.lifespan = duration(parts[4])?;
    let live: Vec<&str> = parts[5].split(',').collect();
    let [policy, lease_s, lease_ns] = live.as_slice() else {
        return None;
    };
    qos.liveliness = match num(policy)? {
        None | Some(1) => LivelinessPolicy::Automatic,
        Some(3) => LivelinessPolicy::ManualByTopic,
        Some(_) => LivelinessPolicy::Unknown,
    };
    qos.liveliness_lease_duration = duration(&format!("{lease_s},{lease_ns}"))?;
    Some(qos)
}

impl fmt::Display for Token {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.key())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The facts' real tokens (rmw_zenoh_cpp 0.2.10 next to rclpy demo nodes).
    const TALKER_MP: &str = "@ros2_lv/0/f60efce6758d919f6932f83718eeed34/0/10/MP/%/%/talker/%chatter/std_msgs::msg::dds_::String_/RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18/::,10:,:,:,,";
    const ROSOUT_MP: &str = "@ros2_lv/0/e9082285dcd48a23ab02c043a2602c27/0/1/MP/%/%/add_two_ints_server/%rosout/rcl_interfaces::msg::dds_::Log_/RIHS01_e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac/:1:,1000:,:10,0:,,";
    const NODE: &str = "@ros2_lv/0/e9082285dcd48a23ab02c043a2602c27/0/0/NN/%/%/add_two_ints_server";
    const CLIENT: &str = "@ros2_lv/0/dae4b8a33e913b775f5f35888814767/0/10/SC/%/%/_ros2cli_requester_example_interfaces_AddTwoInts/%add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a/::,10:,:,:,,";

    #[test]
    fn the_talker_token_hashes_to_the_gid_seen_on_the_wire() {
        assert_eq!(
            gid_of_key(TALKER_MP).as_bytes(),
            &[
                0xa0, 0x03, 0xd7, 0x27, 0x01, 0x2b, 0x11, 0x4c, 0x73, 0x38, 0x3c, 0x3e, 0xcc, 0xc7,
                0xe6, 0x19
            ]
        );
        let token = Token::parse(TALKER_MP).expect("parses");
        assert_eq!(token.gid(), gid_of_key(TALKER_MP));
    }

    #[test]
    fn real_tokens_parse_and_format_back_byte_for_byte() {
        for key in [TALKER_MP, ROSOUT_MP, NODE, CLIENT] {
            let token = Token::parse(key).unwrap_or_else(|e| panic!("{key}: {e}"));
            assert_eq!(token.key(), key);
        }
        let talker = Token::parse(TALKER_MP).expect("parses");
        assert_eq!(talker.kind, EntityKind::Publisher);
        assert_eq!((talker.node_id, talker.entity_id), (0, 10));
        assert_eq!(talker.namespace, "/");
        assert_eq!(talker.enclave, "/");
        let topic = talker.topic.expect("topic");
        assert_eq!(topic.name, "/chatter");
        assert_eq!(topic.qos.depth, 10);
        assert_eq!(topic.qos.reliability, ReliabilityPolicy::Reliable);
        let rosout = Token::parse(ROSOUT_MP)
            .expect("parses")
            .topic
            .expect("topic");
        assert_eq!(rosout.qos.durability, DurabilityPolicy::TransientLocal);
        assert_eq!(rosout.qos.depth, 1000);
        assert_eq!(
            rosout.qos.lifespan,
            QosDuration::Finite(std::time::Duration::from_secs(10))
        );
        assert!(rosout.qos.deadline.is_infinite());
        let client = Token::parse(CLIENT).expect("parses");
        assert_eq!(client.zid.len(), 31, "leading zeros dropped");
        assert_eq!(client.kind, EntityKind::Client);
    }

    #[test]
    fn qos_keyexpr_leaves_defaults_empty() {
        assert_eq!(qos_to_keyexpr(&Qos::default_profile()), "::,10:,:,:,,");
        assert_eq!(
            qos_to_keyexpr(&Qos::default_profile().keep_last(42)),
            "::,:,:,:,,"
        );
        let mut qos = Qos::default_profile().keep_last(1000);
        qos.durability = DurabilityPolicy::TransientLocal;
        qos.lifespan = QosDuration::Finite(std::time::Duration::from_secs(10));
        assert_eq!(qos_to_keyexpr(&qos), ":1:,1000:,:10,0:,,");
        let mut be = Qos::default_profile().keep_all();
        be.reliability = ReliabilityPolicy::BestEffort;
        be.deadline = QosDuration::Finite(std::time::Duration::from_millis(1500));
        let s = qos_to_keyexpr(&be);
        assert_eq!(s, "2::2,10:1,500000000:,:,,");
        assert_eq!(
            qos_to_keyexpr(&Qos::default_profile().keep_last(0)),
            "::,:,:,:,,"
        );
        let back = keyexpr_to_qos(&s).expect("parses");
        assert_eq!(back.reliability, ReliabilityPolicy::BestEffort);
        assert_eq!(back.history, HistoryPolicy::KeepAll);
        assert_eq!(back.deadline, be.deadline);
    }

    #[test]
    fn malformed_tokens_are_refused() {
        for (key, want) in [
            ("@ros2_lv/0/abc/0/0/XX/%/%/n", TokenError::Kind),
            ("other/0/abc/0/0/NN/%/%/n", TokenError::Prefix),
            (
                "@ros2_lv/0/abc/0/0/NN/%/%",
                TokenError::Parts { found: 8, want: 9 },
            ),
            ("@ros2_lv/0/xyz/0/0/NN/%/%/n", TokenError::Zid),
            ("@ros2_lv/0/abc/a/0/NN/%/%/n", TokenError::Number("node id")),
            (
                "@ros2_lv/0/abc/0/1/MP/%/%/n/%t/T/RIHS01_00/::,:,:,:,,",
                TokenError::TypeHash,
            ),
        ] {
            assert_eq!(Token::parse(key), Err(want), "{key}");
        }
        let unset = TALKER_MP.replace(
            "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18",
            &TypeHash::ZERO.to_string(),
        );
        let token = Token::parse(&unset).expect("the unset hash is read");
        assert_eq!(token.key(), unset);
        let bad_qos = TALKER_MP.replace("::,10:,:,:,,", "::,10:,:,:,");
        assert_eq!(Token::parse(&bad_qos), Err(TokenError::Qos));
    }

    #[test]
    fn names_are_mangled_with_percent() {
        assert_eq!(mangle("/"), "%");
        assert_eq!(mangle(""), "%");
        assert_eq!(mangle("/robot1/chatter"), "%robot1%chatter");
        assert_eq!(demangle("%robot1%chatter"), "/robot1/chatter");
    }
}
