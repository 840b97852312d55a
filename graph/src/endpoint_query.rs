//! Endpoint information by topic (rmw_dds_common `get_writers_info_by_topic` /
//! `get_readers_info_by_topic`) and by service (rmw rolling `get_service_endpoint_info.h`;
//! rmw_fastrtps_shared_cpp rolling `rmw_get_endpoint_info_by_service.cpp`).

use std::collections::BTreeMap;

use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::names::{
    ROS_SERVICE_REQUESTER_PREFIX, ROS_SERVICE_RESPONSE_PREFIX, ROS_TOPIC_PREFIX,
    SERVICE_REPLY_SUFFIX, SERVICE_REQUEST_SUFFIX,
};
use horus_ros_rmw::qos::EndpointKind;

use crate::cache::{GraphCache, TopicEntry};
use crate::endpoint::{EndpointEntry, GuidPrefix};
use crate::error::GraphError;
use crate::event::GraphEndpoint;
use crate::info::{ServiceEndpointInfo, ServiceEndpointType, TopicEndpointInfo, TopicEndpointType};
use crate::query::{demangle_service_type, demangle_type};

/// Identity used to pair a service's reader and writer: participant + reported node.
type PairKey<'a> = (GuidPrefix, &'a str, &'a str);

impl GraphCache {
    /// The endpoints of `kind` on a DDS topic, in GID order, with the topic's entry.
    fn topic_endpoints(
        &self,
        dds_topic: &str,
        kind: EndpointKind,
    ) -> Option<(&TopicEntry, impl Iterator<Item = &EndpointEntry>)> {
        let topic = self.index.topics.get(dds_topic)?;
        let endpoints = topic
            .gids(kind)
            .iter()
            .filter_map(|gid| self.endpoints.get(gid));
        Some((topic, endpoints))
    }

    fn topic_endpoints_info(
        &self,
        topic: &str,
        no_mangle: bool,
        kind: EndpointKind,
    ) -> Vec<TopicEndpointInfo> {
        let dds_topic = if no_mangle {
            topic.to_owned()
        } else {
            format!("{ROS_TOPIC_PREFIX}{topic}")
        };
        let endpoint_type = match kind {
            EndpointKind::Writer => TopicEndpointType::Publisher,
            EndpointKind::Reader => TopicEndpointType::Subscription,
        };
        let Some((topic, endpoints)) = self.topic_endpoints(&dds_topic, kind) else {
            return Vec::new();
        };
        endpoints
            .map(|e| {
                let creator = self.creator(e);
                let (node_name, node_namespace) = creator.name_and_namespace();
                TopicEndpointInfo {
                    node_name: node_name.to_owned(),
                    node_namespace: node_namespace.to_owned(),
                    // rmw_fastrtps / rmw_cyclonedds (jazzy) `__rmw_get_publishers_info_by_topic`:
                    // `_identity_demangle` with `no_mangle`, else `_demangle_if_ros_type`.
                    topic_type: if no_mangle {
                        e.dds_type_name.clone()
                    } else {
                        topic.types.get(e.dds_type_name.as_str()).map_or_else(
                            || demangle_type(&e.dds_type_name),
                            |u| u.message_type.clone(),
                        )
                    },
                    topic_type_hash: e.type_hash,
                    endpoint_type,
                    endpoint_gid: e.gid,
                    qos_profile: e.qos,
                }
            })
            .collect()
    }

    /// Publishers of a topic, in GID order. `topic` is a ROS name (`/chatter`) and each type is
    /// demangled (`std_msgs/msg/String`); with `no_mangle`, `topic` is the DDS topic name
    /// itself and each type the DDS type name as is, as in rmw. An unknown topic gives an empty
    /// list.
    pub fn publishers_info_by_topic(&self, topic: &str, no_mangle: bool) -> Vec<TopicEndpointInfo> {
        self.topic_endpoints_info(topic, no_mangle, EndpointKind::Writer)
    }

    /// Subscriptions of a topic, in GID order (see [`Self::publishers_info_by_topic`]).
    pub fn subscriptions_info_by_topic(
        &self,
        topic: &str,
        no_mangle: bool,
    ) -> Vec<TopicEndpointInfo> {
        self.topic_endpoints_info(topic, no_mangle, EndpointKind::Reader)
    }

    /// Endpoints of `kind` on `dds_topic`, grouped by (participant, node) in GID order.
    fn endpoints_by_node(
        &self,
        dds_topic: &str,
        kind: EndpointKind,
    ) -> BTreeMap<PairKey<'_>, Vec<&EndpointEntry>> {
        let mut out: BTreeMap<PairKey<'_>, Vec<&EndpointEntry>> = BTreeMap::new();
        let Some((_, endpoints)) = self.topic_endpoints(dds_topic, kind) else {
            return out;
        };
        for e in endpoints {
            let (name, namespace) = self.creator(e).name_and_namespace();
            out.entry((e.participant_prefix(), name, namespace))
                .or_default()
                .push(e);
        }
        out
    }

    /// `pkg/srv/Name` of an endpoint's request or response type, demangled when it was indexed.
    fn service_type_of(&self, dds_topic: &str, e: &EndpointEntry) -> Option<String> {
        match self
            .index
            .topics
            .get(dds_topic)
            .and_then(|topic| topic.types.get(e.dds_type_name.as_str()))
        {
            Some(used) => used.service_type.clone(),
            None => demangle_service_type(&e.dds_type_name),
        }
    }

    /// Pairs the readers on `reader_topic` with the writers on `writer_topic` of the same
    /// participant and node, the n-th reader with the n-th writer in GID order.
    fn service_endpoints_info(
        &self,
        reader_topic: &str,
        writer_topic: &str,
        endpoint_type: ServiceEndpointType,
    ) -> Vec<ServiceEndpointInfo> {
        let readers = self.endpoints_by_node(reader_topic, EndpointKind::Reader);
        if readers.is_empty() {
            return Vec::new();
        }
        let mut writers = self.endpoints_by_node(writer_topic, EndpointKind::Writer);
        let mut out = Vec::new();
        for (key, node_readers) in readers {
            let Some(node_writers) = writers.remove(&key) else {
                continue;
            };
            for (reader, writer) in node_readers.into_iter().zip(node_writers) {
                let service_type = self
                    .service_type_of(reader_topic, reader)
                    .or_else(|| self.service_type_of(writer_topic, writer))
                    .unwrap_or_else(|| reader.dds_type_name.clone());
                let service_type_hash = self
                    .service_type_hashes
                    .get(&service_type)
                    .copied()
                    .unwrap_or(TypeHash::ZERO);
                out.push(ServiceEndpointInfo {
                    node_name: key.1.to_owned(),
                    node_namespace: key.2.to_owned(),
                    service_type,
                    service_type_hash,
                    endpoint_type,
                    endpoint_gids: vec![reader.gid, writer.gid],
                    qos_profiles: vec![reader.qos, writer.qos],
                    endpoint_type_hashes: vec![reader.type_hash, writer.type_hash],
                });
            }
        }
        out.sort_by_key(|info| {
            info.endpoint_gids
                .first()
                .copied()
                .unwrap_or(Gid::default())
        });
        out
    }

    /// Servers of a service, in request-reader GID order: each is a request reader on
    /// `rq/<service>Request` paired with a response writer on `rr/<service>Reply` of the same
    /// participant and node; GIDs and QoS reader then writer.
    ///
    /// A half-visible server (only one of its two endpoints discovered so far) is left out
    /// until both are known, so a listed server is one that can answer. An unknown service
    /// gives an empty list; `no_mangle` is an error on DDS.
    pub fn servers_info_by_service(
        &self,
        service: &str,
        no_mangle: bool,
    ) -> Result<Vec<ServiceEndpointInfo>, GraphError> {
        if no_mangle {
            return Err(GraphError::NoMangleUnsupported);
        }
        Ok(self.service_endpoints_info(
            &format!("{ROS_SERVICE_REQUESTER_PREFIX}{service}{SERVICE_REQUEST_SUFFIX}"),
            &format!("{ROS_SERVICE_RESPONSE_PREFIX}{service}{SERVICE_REPLY_SUFFIX}"),
            ServiceEndpointType::Server,
        ))
    }

    /// Clients of a service, in response-reader GID order: each is a response reader on
    /// `rr/<service>Reply` paired with a request writer on `rq/<service>Request` of the same
    /// participant and node; GIDs and QoS reader then writer. Half-visible clients are left
    /// out, as in [`Self::servers_info_by_service`].
    pub fn clients_info_by_service(
        &self,
        service: &str,
        no_mangle: bool,
    ) -> Result<Vec<ServiceEndpointInfo>, GraphError> {
        if no_mangle {
            return Err(GraphError::NoMangleUnsupported);
        }
        Ok(self.service_endpoints_info(
            &format!("{ROS_SERVICE_RESPONSE_PREFIX}{service}{SERVICE_REPLY_SUFFIX}"),
            &format!("{ROS_SERVICE_REQUESTER_PREFIX}{service}{SERVICE_REQUEST_SUFFIX}"),
            ServiceEndpointType::Client,
        ))
    }

    /// One reader or writer as [`GraphEvent`](crate::GraphEvent)s report it, its node as known
    /// now; `None` if its GID is not known.
    pub fn endpoint(&self, gid: Gid) -> Option<GraphEndpoint> {
        self.endpoints.get(&gid).map(|e| self.graph_endpoint(e))
    }

    /// Every reader and writer, ROS or not, in GID order, as [`GraphEvent`](crate::GraphEvent)s
    /// report them (the endpoints a consumer of events started now has not been told of).
    pub fn all_endpoints(&self) -> Vec<GraphEndpoint> {
        let mut all: Vec<GraphEndpoint> = self
            .endpoints
            .values()
            .map(|e| self.graph_endpoint(e))
            .collect();
        all.sort_by_key(|e| e.gid);
        all
    }

    /// Whether at least one server of `service` has both its request reader and its response
    /// writer known (so a request sent now can be answered).
    pub fn service_is_available(&self, service: &str) -> bool {
        self.servers_info_by_service(service, false)
            .is_ok_and(|servers| !servers.is_empty())
    }
}
