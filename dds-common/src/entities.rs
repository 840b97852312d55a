//! The node ↔ endpoint bookkeeping of one participant, as rmw_dds_common's `GraphCache` keeps it
//! for the local participant (`add_node`, `associate_reader/writer`, `dissociate_*`, `remove_node`).
//!
//! Pure data: every mutation returns the whole [`ParticipantEntitiesInfo`] to publish on
//! `ros_discovery_info`, because rmw_dds_common republishes the participant's full message on every
//! node or endpoint change (rmw_dds_common `graph_cache.cpp`, jazzy).

use horus_ros_msgs::rmw_dds_common::{Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};

/// Identifies one node inside a participant (node names may repeat, as in ROS).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeKey(u64);

impl NodeKey {
    /// The number (the backend contract's node id).
    pub fn id(self) -> u64 {
        self.0
    }
}

/// Which list of a node an endpoint GID belongs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndpointSide {
    /// A data reader.
    Reader,
    /// A data writer.
    Writer,
}

/// All nodes of one participant, in creation order.
#[derive(Debug)]
pub struct LocalEntities {
    participant_gid: Gid,
    next_key: u64,
    nodes: Vec<(NodeKey, NodeEntitiesInfo)>,
}

impl LocalEntities {
    /// An empty participant.
    pub fn new(participant_gid: Gid) -> Self {
        Self {
            participant_gid,
            next_key: 0,
            nodes: Vec::new(),
        }
    }

    /// Adds a node (appended, as `GraphCache::add_node`).
    pub fn add_node(&mut self, namespace: &str, name: &str) -> (NodeKey, ParticipantEntitiesInfo) {
        let key = NodeKey(self.next_key);
        self.next_key += 1;
        self.nodes.push((
            key,
            NodeEntitiesInfo {
                node_namespace: namespace.to_owned(),
                node_name: name.to_owned(),
                reader_gid_seq: Vec::new(),
                writer_gid_seq: Vec::new(),
            },
        ));
        (key, self.message())
    }

    /// Removes a node; `None` if it was not there.
    pub fn remove_node(&mut self, key: NodeKey) -> Option<ParticipantEntitiesInfo> {
        let before = self.nodes.len();
        self.nodes.retain(|(k, _)| *k != key);
        (self.nodes.len() != before).then(|| self.message())
    }

    /// Lists an endpoint under a node; `None` if the node is unknown.
    pub fn associate(
        &mut self,
        key: NodeKey,
        side: EndpointSide,
        gid: Gid,
    ) -> Option<ParticipantEntitiesInfo> {
        let node = self.node_mut(key)?;
        match side {
            EndpointSide::Reader => node.reader_gid_seq.push(gid),
            EndpointSide::Writer => node.writer_gid_seq.push(gid),
        }
        Some(self.message())
    }

    /// Removes an endpoint from a node; `None` if nothing changed.
    pub fn dissociate(
        &mut self,
        key: NodeKey,
        side: EndpointSide,
        gid: Gid,
    ) -> Option<ParticipantEntitiesInfo> {
        let node = self.node_mut(key)?;
        let list = match side {
            EndpointSide::Reader => &mut node.reader_gid_seq,
            EndpointSide::Writer => &mut node.writer_gid_seq,
        };
        let before = list.len();
        list.retain(|g| *g != gid);
        (list.len() != before).then(|| self.message())
    }

    /// The message describing the participant now.
    pub fn message(&self) -> ParticipantEntitiesInfo {
        ParticipantEntitiesInfo {
            gid: self.participant_gid,
            node_entities_info_seq: self.nodes.iter().map(|(_, n)| n.clone()).collect(),
        }
    }

    fn node_mut(&mut self, key: NodeKey) -> Option<&mut NodeEntitiesInfo> {
        self.nodes
            .iter_mut()
            .find(|(k, _)| *k == key)
            .map(|(_, n)| n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gid(s: &str) -> Gid {
        let mut data = [0u8; 16];
        for (d, b) in data.iter_mut().zip(s.bytes()) {
            *d = b;
        }
        Gid::from_bytes(data)
    }

    #[test]
    fn every_change_gives_the_whole_participant() {
        let mut e = LocalEntities::new(gid("participant"));
        let (a, m) = e.add_node("/", "a");
        assert_eq!(m.node_entities_info_seq.len(), 1);
        let (b, _) = e.add_node("/ns", "a");
        let m = e
            .associate(a, EndpointSide::Writer, gid("w1"))
            .expect("node a exists");
        assert_eq!(m.gid, gid("participant"));
        assert_eq!(m.node_entities_info_seq[0].writer_gid_seq, vec![gid("w1")]);
        assert_eq!(m.node_entities_info_seq[1].node_namespace, "/ns");
        let m = e
            .associate(b, EndpointSide::Reader, gid("r1"))
            .expect("node b exists");
        assert_eq!(m.node_entities_info_seq[1].reader_gid_seq, vec![gid("r1")]);
        assert!(
            e.dissociate(b, EndpointSide::Writer, gid("r1")).is_none(),
            "wrong side changes nothing"
        );
        let m = e
            .dissociate(b, EndpointSide::Reader, gid("r1"))
            .expect("was listed");
        assert!(m.node_entities_info_seq[1].reader_gid_seq.is_empty());
        let m = e.remove_node(a).expect("node a exists");
        assert_eq!(m.node_entities_info_seq.len(), 1);
        assert_eq!(m.node_entities_info_seq[0].node_namespace, "/ns");
        assert!(e.remove_node(a).is_none());
        assert!(e.associate(a, EndpointSide::Reader, gid("x")).is_none());
    }
}
