//! Tests of the `names` module, ported from the ROS 2 Jazzy test suites cited
//! in each file.

mod dds_type_names;
mod expand_topic_name;
mod fq_node_name;
mod hidden;
mod mangling;
mod validate_full_topic_name;
mod validate_namespace;
mod validate_node_name;
mod validate_topic_name;
