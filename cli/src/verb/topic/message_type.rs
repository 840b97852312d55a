//! A message type known at run time, as the topic verbs find it: compiled in, else its
//! interface file in a package on `AMENT_PREFIX_PATH` ([`MessageType::installed`]), else the
//! `~/get_type_description` of a node that publishes or subscribes to it
//! ([`MessageType::from_graph`]). Each verb words the errors as its ros2cli verb does.

use std::time::Duration;

use horus_ros_msgs::{dds_type_name, TypeDescription, TypeHash};

use crate::dynamic::compiled::compiled_type;
use crate::dynamic::Schema;
use crate::session::Session;
use crate::verb::interface::catalog::Catalog;
use crate::verb::interface::definition;
use crate::verb::service::call::describe;
use crate::CliError;

/// A message type: its structs and RIHS01 hash.
pub struct MessageType {
    /// `pkg/msg/Name`.
    pub name: String,
    /// The structs of the type and of every type it uses.
    pub schema: Schema,
    /// The RIHS01 hash of the type.
    pub hash: TypeHash,
}

impl MessageType {
    /// The type from its description (which must contain it and what it uses); why not.
    fn from_description(name: &str, description: &TypeDescription) -> Result<Self, String> {
        let schema = Schema::from_description(description)
            .and_then(|s| s.check(name).map(|()| s))
            .map_err(|e| e.to_string())?;
        Ok(Self {
            name: name.to_owned(),
            schema,
            hash: description.compute_type_hash(),
        })
    }

    /// The type as horus-ros knows it without a graph: compiled in, else from its interface file
    /// on `AMENT_PREFIX_PATH`; `Ok(Err(why))` when neither has it (why no file was found). A
    /// description that cannot be used is `unusable(why)`.
    pub fn installed(
        name: &str,
        unusable: impl Fn(String) -> CliError,
    ) -> Result<Result<Self, String>, CliError> {
        let description = if let Some(t) = compiled_type(name) {
            (t.describe)()
        } else {
            let catalog = Catalog::from_env();
            let path = match catalog.index.find_interface(name) {
                Ok(path) => path,
                Err(e) => return Ok(Err(e.to_string())),
            };
            let (package, _, _) = definition::split_type(name)?;
            definition::describe_files(&catalog, package, &path, name)?
        };
        Self::from_description(name, &description)
            .map(Ok)
            .map_err(unusable)
    }

    /// The type as a node of the graph that publishes or subscribes to it describes it
    /// (`~/get_type_description`), waiting at most `timeout` for each node asked;
    /// `not_described(why)` names the nodes asked and why they failed, `unusable(why)` is a
    /// description that cannot be used.
    pub fn from_graph(
        session: &Session,
        name: &str,
        timeout: Duration,
        not_described: impl FnOnce(String) -> CliError,
        unusable: impl Fn(String) -> CliError,
    ) -> Result<Self, CliError> {
        let description = describe::fetch_message(&session.node, &session.graph, name, timeout)
            .map_err(not_described)?;
        Self::from_description(name, &description).map_err(unusable)
    }

    /// `pkg::msg::dds_::Name_`.
    pub fn dds_type_name(&self) -> String {
        dds_type_name(&self.name)
    }
}
