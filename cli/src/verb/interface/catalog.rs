//! [`Catalog`]: the interfaces the CLI knows without a graph — those of the packages on
//! `AMENT_PREFIX_PATH` (the ament resource index, as rosidl_runtime_py jazzy
//! `get_interfaces.py` reads it) and the types compiled into horus-ros.

use std::collections::{BTreeMap, BTreeSet};

use horus_ros_codegen::ament::{AmentIndex, InterfaceKind, LookupError};

use crate::dynamic::compiled::compiled_types;

/// Package name → interface names (`msg/String`, as rosidl_runtime_py returns them).
pub type ByPackage = BTreeMap<String, BTreeSet<String>>;

/// The installed and the compiled interfaces.
pub struct Catalog {
    /// The resource index of `AMENT_PREFIX_PATH`.
    pub index: AmentIndex,
}

impl Catalog {
    /// The catalog of `AMENT_PREFIX_PATH` and the compiled types.
    pub fn from_env() -> Self {
        Self {
            index: AmentIndex::from_env(),
        }
    }

    /// Every interface of one kind, by package (rosidl_runtime_py `get_message_interfaces`,
    /// `get_service_interfaces`, `get_action_interfaces` of all packages), compiled types
    /// included. Packages without interfaces of the kind are left out.
    pub fn of_kind(&self, kind: InterfaceKind) -> ByPackage {
        let mut out = ByPackage::new();
        for package in self.index.interface_packages() {
            // A package listed without its `packages` marker: rosidl_runtime_py fails on it;
            // it is skipped here.
            let Ok(interfaces) = self.index.interfaces(&package) else {
                continue;
            };
            for i in interfaces.into_iter().filter(|i| i.kind == kind) {
                out.entry(package.clone()).or_default().insert(format!(
                    "{}/{}",
                    kind.namespace(),
                    i.name
                ));
            }
        }
        for t in compiled_types() {
            if let [package, namespace, name] = t.name.split('/').collect::<Vec<_>>()[..] {
                if InterfaceKind::from_namespace(namespace) == Some(kind) {
                    out.entry(package.to_owned())
                        .or_default()
                        .insert(format!("{namespace}/{name}"));
                }
            }
        }
        out
    }

    /// The packages with interfaces (rosidl_runtime_py `get_interface_packages`), compiled
    /// ones included.
    pub fn packages(&self) -> BTreeSet<String> {
        let mut out: BTreeSet<String> = self.index.interface_packages().into_iter().collect();
        out.extend(compiled_types().iter().filter_map(|t| {
            t.name
                .split_once('/')
                .map(|(package, _)| package.to_owned())
        }));
        out
    }

    /// The interfaces of one package: with `kinds` empty, every (not hidden) entry of its
    /// resource (rosidl_runtime_py `get_interfaces`), else those of each kind in turn; compiled
    /// types included. A package neither installed nor compiled in is an error
    /// (`Unknown package '…'`).
    pub fn package(
        &self,
        package: &str,
        kinds: &[InterfaceKind],
    ) -> Result<Vec<String>, LookupError> {
        let compiled: Vec<&str> = compiled_types()
            .iter()
            .filter_map(|t| t.name.strip_prefix(package)?.strip_prefix('/'))
            .collect();
        let installed = match self.index.interface_names(package) {
            Ok(names) => names,
            Err(LookupError::UnknownPackage(_)) if !compiled.is_empty() => Vec::new(),
            Err(e) => return Err(e),
        };
        let mut all: BTreeSet<String> = installed.into_iter().collect();
        all.extend(compiled.iter().map(|s| (*s).to_owned()));
        if kinds.is_empty() {
            return Ok(all.into_iter().collect());
        }
        let mut out = Vec::new();
        for kind in kinds {
            let prefix = format!("{}/", kind.namespace());
            out.extend(all.iter().filter(|n| n.starts_with(&prefix)).cloned());
        }
        Ok(out)
    }
}
