//! The ament resource index: which packages of an install (the prefixes of `AMENT_PREFIX_PATH`)
//! have interfaces, which interfaces each has, and where their files are.
//!
//! Follows ament_index_python (jazzy `resources.py`, `search_paths.py`): the prefixes are
//! `AMENT_PREFIX_PATH` split on `:`, empty and missing ones dropped; a resource of type `T` named
//! `N` is the file `<prefix>/share/ament_index/resource_index/T/N`, and the first prefix that has
//! it wins. rosidl registers a package's interfaces as the resource `rosidl_interfaces/<pkg>`,
//! one path a line relative to `<prefix>/share/<pkg>` (`msg/String.msg`, `msg/String.idl`,
//! `srv/Empty_Request.msg`, …); rosidl_runtime_py (jazzy `get_interfaces.py`) reads them, hiding
//! every name with a `_` (the request / response / goal parts).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The folder of the resource index under a prefix.
const RESOURCE_INDEX: &str = "share/ament_index/resource_index";

/// The resource type under which rosidl lists a package's interface files.
pub const INTERFACES_RESOURCE: &str = "rosidl_interfaces";

/// The resource type every installed package has.
pub const PACKAGES_RESOURCE: &str = "packages";

/// What an interface is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum InterfaceKind {
    /// A message (`msg/`).
    Message,
    /// A service (`srv/`).
    Service,
    /// An action (`action/`).
    Action,
}

impl InterfaceKind {
    /// The namespace of this kind in type names and in `share/<pkg>`: `msg`, `srv` or `action`.
    pub fn namespace(self) -> &'static str {
        match self {
            Self::Message => "msg",
            Self::Service => "srv",
            Self::Action => "action",
        }
    }

    /// The kind of a namespace (`msg`, `srv`, `action`).
    pub fn from_namespace(namespace: &str) -> Option<Self> {
        match namespace {
            "msg" => Some(Self::Message),
            "srv" => Some(Self::Service),
            "action" => Some(Self::Action),
            _ => None,
        }
    }
}

/// One interface a package lists in its `rosidl_interfaces` resource.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InterfaceFile {
    /// Message, service or action.
    pub kind: InterfaceKind,
    /// The interface's name (`String`).
    pub name: String,
    /// Its definition file: the `.msg` / `.srv` / `.action` file when the package lists one,
    /// else its `.idl`.
    pub path: PathBuf,
}

impl InterfaceFile {
    /// `pkg/msg/Name` for package `package`.
    pub fn type_name(&self, package: &str) -> String {
        format!("{package}/{}/{}", self.kind.namespace(), self.name)
    }
}

/// Why an index lookup failed. The messages are rosidl_runtime_py's.
#[derive(Debug, thiserror::Error)]
pub enum LookupError {
    /// No prefix has the package (rosidl_runtime_py `get_interfaces`, `get_interface_path`).
    #[error("Unknown package '{0}'")]
    UnknownPackage(String),
    /// A malformed type name (rosidl_runtime_py `get_interface_path`).
    #[error("Invalid name '{name}'. {reason}")]
    InvalidName {
        /// The name given.
        name: String,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The package exists but has no such interface file (rosidl_runtime_py
    /// `get_interface_path`, which names the last path it tried).
    #[error("Could not find the interface '{}'", .0.display())]
    NoInterface(PathBuf),
    /// A resource file could not be read.
    #[error("Could not open the resource '{name}' of type '{resource_type}': {cause}")]
    Unreadable {
        /// The resource type.
        resource_type: String,
        /// The resource name.
        name: String,
        /// The error.
        cause: std::io::Error,
    },
}

/// The resource index of a list of install prefixes.
#[derive(Clone, Debug, Default)]
pub struct AmentIndex {
    prefixes: Vec<PathBuf>,
}

impl AmentIndex {
    /// The prefixes of `AMENT_PREFIX_PATH` (none when it is unset or empty).
    pub fn from_env() -> Self {
        let value = std::env::var_os("AMENT_PREFIX_PATH").unwrap_or_default();
        Self::from_prefixes(std::env::split_paths(&value).collect())
    }

    /// These prefixes, in order; empty and missing ones are dropped, as ament_index_python's
    /// `get_search_paths` does.
    pub fn from_prefixes(prefixes: Vec<PathBuf>) -> Self {
        Self {
            prefixes: prefixes
                .into_iter()
                .filter(|p| !p.as_os_str().is_empty() && p.exists())
                .collect(),
        }
    }

    /// The prefixes searched, in order.
    pub fn prefixes(&self) -> &[PathBuf] {
        &self.prefixes
    }

    /// `<prefix>/share/<package>` of the first prefix where the package has interface folders
    /// (`msg/`, `srv/` or `action/`), registered in the resource index or not.
    pub fn package_share(&self, package: &str) -> Option<PathBuf> {
        self.prefixes
            .iter()
            .map(|p| p.join("share").join(package))
            .find(|d| ["msg", "srv", "action"].iter().any(|k| d.join(k).is_dir()))
    }

    /// ament_index_python `get_resources`: every resource of `resource_type` with the prefix it
    /// is found in first (subfolders and names starting with `.` skipped).
    pub fn resources(&self, resource_type: &str) -> BTreeMap<String, PathBuf> {
        let mut out = BTreeMap::new();
        for prefix in &self.prefixes {
            let Ok(entries) = std::fs::read_dir(prefix.join(RESOURCE_INDEX).join(resource_type))
            else {
                continue;
            };
            for entry in entries.flatten() {
                let Ok(name) = entry.file_name().into_string() else {
                    continue;
                };
                if name.starts_with('.') || entry.path().is_dir() {
                    continue;
                }
                out.entry(name).or_insert_with(|| prefix.clone());
            }
        }
        out
    }

    /// ament_index_python `has_resource`: the first prefix that has the resource.
    pub fn resource_prefix(&self, resource_type: &str, name: &str) -> Option<&Path> {
        if name.is_empty() || name.contains(['/', '\\']) {
            return None;
        }
        self.prefixes
            .iter()
            .find(|p| {
                p.join(RESOURCE_INDEX)
                    .join(resource_type)
                    .join(name)
                    .is_file()
            })
            .map(PathBuf::as_path)
    }

    /// ament_index_python `get_resource`: the content of the resource and its prefix.
    pub fn resource(
        &self,
        resource_type: &str,
        name: &str,
    ) -> Result<Option<(String, &Path)>, LookupError> {
        let Some(prefix) = self.resource_prefix(resource_type, name) else {
            return Ok(None);
        };
        let path = prefix.join(RESOURCE_INDEX).join(resource_type).join(name);
        let content = std::fs::read_to_string(&path).map_err(|source| LookupError::Unreadable {
            resource_type: resource_type.to_owned(),
            name: name.to_owned(),
            cause: source,
        })?;
        Ok(Some((content, prefix)))
    }

    /// The packages that register interfaces (rosidl_runtime_py `get_interface_packages`),
    /// sorted.
    pub fn interface_packages(&self) -> Vec<String> {
        self.resources(INTERFACES_RESOURCE).into_keys().collect()
    }

    /// Whether the package is installed (the `packages` resource).
    pub fn has_package(&self, package: &str) -> bool {
        self.resource_prefix(PACKAGES_RESOURCE, package).is_some()
    }

    /// The raw lines of a package's `rosidl_interfaces` resource (`msg/String.msg`, …), hidden
    /// ones included; `Ok(None)` for an installed package without interfaces (rosidl_runtime_py
    /// `_get_interfaces`).
    pub fn interface_entries(
        &self,
        package: &str,
    ) -> Result<Option<(Vec<String>, PathBuf)>, LookupError> {
        if !self.has_package(package) {
            return Err(LookupError::UnknownPackage(package.to_owned()));
        }
        Ok(self
            .resource(INTERFACES_RESOURCE, package)?
            .map(|(content, prefix)| {
                (
                    content.lines().map(str::to_owned).collect(),
                    prefix.to_path_buf(),
                )
            }))
    }

    /// The messages, services and actions of a package, sorted by kind then name: the entries
    /// of its `rosidl_interfaces` resource without `_` (rosidl_runtime_py's
    /// `get_message_interfaces` etc.: `.msg` / `.srv` / `.action` or `.idl` files under
    /// `msg/`, `srv/`, `action/`), each with its `.msg`/`.srv`/`.action` file when listed, else
    /// its `.idl`.
    pub fn interfaces(&self, package: &str) -> Result<Vec<InterfaceFile>, LookupError> {
        let Some((entries, prefix)) = self.interface_entries(package)? else {
            return Ok(Vec::new());
        };
        let share = prefix.join("share").join(package);
        let mut found: BTreeMap<(InterfaceKind, String), PathBuf> = BTreeMap::new();
        for entry in entries {
            if entry.contains('_') {
                continue;
            }
            let Some((namespace, file)) = entry.split_once('/') else {
                continue;
            };
            let Some(kind) = InterfaceKind::from_namespace(namespace) else {
                continue;
            };
            let Some((name, extension)) = file.rsplit_once('.') else {
                continue;
            };
            if name.is_empty() || name.contains('/') {
                continue;
            }
            let own = extension == namespace;
            if !own && extension != "idl" {
                continue;
            }
            let key = (kind, name.to_owned());
            // The .msg/.srv/.action file wins over the .idl.
            if own || !found.contains_key(&key) {
                found.insert(key, share.join(&entry));
            }
        }
        Ok(found
            .into_iter()
            .map(|((kind, name), path)| InterfaceFile { kind, name, path })
            .collect())
    }

    /// The names of every (not hidden) entry of a package's resource without its extension
    /// (`msg/String`, `srv/Empty`, any other namespace too), sorted: rosidl_runtime_py
    /// `get_interfaces`.
    pub fn interface_names(&self, package: &str) -> Result<Vec<String>, LookupError> {
        let Some((entries, _)) = self.interface_entries(package)? else {
            return Ok(Vec::new());
        };
        let names: BTreeSet<String> = entries
            .iter()
            .filter(|e| !e.contains('_'))
            .map(|e| e.rsplit_once('.').map_or(e.as_str(), |(n, _)| n).to_owned())
            .collect();
        Ok(names.into_iter().collect())
    }

    /// rosidl_runtime_py `get_interface_path`: the file of `pkg/msg/Name` (or any
    /// `pkg/ns/Name`): `<prefix>/share/pkg/ns/Name.ns` if it exists, else `….idl`; a name with
    /// an extension (`pkg/msg/Name.msg`) is that file.
    pub fn find_interface(&self, type_name: &str) -> Result<PathBuf, LookupError> {
        let invalid = |reason| LookupError::InvalidName {
            name: type_name.to_owned(),
            reason,
        };
        let parts: Vec<&str> = type_name.split('/').collect();
        if parts.len() < 2 {
            return Err(invalid("Expected at least two parts separated by '/'"));
        }
        if parts.iter().any(|p| p.is_empty()) {
            return Err(invalid("Must not contain empty parts"));
        }
        if parts.contains(&"..") {
            return Err(invalid("Must not contain '..'"));
        }
        let prefix = self
            .resource_prefix(PACKAGES_RESOURCE, parts[0])
            .ok_or_else(|| LookupError::UnknownPackage(parts[0].to_owned()))?;
        let mut path = prefix.join("share");
        for part in &parts {
            path.push(part);
        }
        let last = parts[parts.len() - 1];
        if !last.contains('.') {
            let parent = parts[parts.len() - 2];
            let with_suffix = path.with_file_name(format!("{last}.{parent}"));
            if with_suffix.exists() {
                return Ok(with_suffix);
            }
            path.set_file_name(format!("{last}.idl"));
        }
        if !path.exists() {
            return Err(LookupError::NoInterface(path));
        }
        Ok(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A prefix with `packages/<pkg>` and `rosidl_interfaces/<pkg>` listing `entries`, each file
    /// created.
    fn prefix(root: &Path, package: &str, entries: &[&str]) {
        let index = root.join(RESOURCE_INDEX);
        std::fs::create_dir_all(index.join(PACKAGES_RESOURCE)).expect("mkdir");
        std::fs::write(index.join(PACKAGES_RESOURCE).join(package), "").expect("write");
        if entries.is_empty() {
            return;
        }
        std::fs::create_dir_all(index.join(INTERFACES_RESOURCE)).expect("mkdir");
        std::fs::write(
            index.join(INTERFACES_RESOURCE).join(package),
            entries.join("\n") + "\n",
        )
        .expect("write");
        for e in entries {
            let file = root.join("share").join(package).join(e);
            std::fs::create_dir_all(file.parent().expect("parent")).expect("mkdir");
            std::fs::write(file, "int32 x\n").expect("write");
        }
    }

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("horus-ament-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("mkdir");
        dir
    }

    #[test]
    fn interfaces_are_listed_without_hidden_parts_and_found_by_type_name() {
        let root = temp("list");
        prefix(
            &root,
            "pkg",
            &[
                "msg/A.idl",
                "msg/A.msg",
                "msg/B.idl",
                "srv/S.idl",
                "srv/S.srv",
                "srv/S_Request.msg",
                "action/Go.action",
            ],
        );
        prefix(&root, "bare", &[]);
        let index = AmentIndex::from_prefixes(vec![root.clone(), root.join("missing")]);
        assert_eq!(index.prefixes(), std::slice::from_ref(&root));
        assert_eq!(index.interface_packages(), ["pkg"]);
        let interfaces = index.interfaces("pkg").expect("pkg");
        let names: Vec<String> = interfaces.iter().map(|i| i.type_name("pkg")).collect();
        assert_eq!(
            names,
            ["pkg/msg/A", "pkg/msg/B", "pkg/srv/S", "pkg/action/Go"]
        );
        assert!(interfaces[0].path.ends_with("share/pkg/msg/A.msg"));
        assert!(interfaces[1].path.ends_with("share/pkg/msg/B.idl"));
        assert!(index.interfaces("bare").expect("bare").is_empty());
        assert_eq!(
            index.interfaces("nope").map_err(|e| e.to_string()),
            Err("Unknown package 'nope'".to_owned())
        );
        assert!(index
            .find_interface("pkg/msg/A")
            .expect("A")
            .ends_with("msg/A.msg"));
        assert!(index
            .find_interface("pkg/msg/B")
            .expect("B")
            .ends_with("msg/B.idl"));
        assert_eq!(
            index.find_interface("pkg/msg/C").map_err(|e| e.to_string()),
            Err(format!(
                "Could not find the interface '{}'",
                root.join("share/pkg/msg/C.idl").display()
            ))
        );
        assert_eq!(
            index.find_interface("x/msg/C").map_err(|e| e.to_string()),
            Err("Unknown package 'x'".to_owned())
        );
        assert_eq!(
            index.find_interface("x").map_err(|e| e.to_string()),
            Err("Invalid name 'x'. Expected at least two parts separated by '/'".to_owned())
        );
        let _ = std::fs::remove_dir_all(&root);
    }
}
