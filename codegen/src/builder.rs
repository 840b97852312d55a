//! [`Builder`]: the `build.rs` entry point, in the manner of prost-build / tonic-build.
//!
//! ```no_run
//! // build.rs
//! fn main() -> Result<(), Box<dyn std::error::Error>> {
//!     horus_ros_codegen::Builder::new()
//!         .package_dir("interfaces/my_robot_msgs")
//!         .generate()?;
//!     Ok(())
//! }
//! // src/lib.rs: include!(concat!(env!("OUT_DIR"), "/interfaces.rs"));
//! // then my_robot_msgs::msg::Status, my_robot_msgs::srv::Reset, …
//! ```
//!
//! A type that a generated one uses is found, in this order: among the packages generated in the
//! same run; among the types compiled into horus-ros-msgs ([`crate::compiled`]); in a package of
//! an install prefix ([`Builder::prefix`], and `AMENT_PREFIX_PATH` unless
//! [`Builder::ament_prefix_path`] turns it off), which is then generated too.

use std::cell::RefCell;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::ament::AmentIndex;
use crate::compiled;
use crate::definition::{BaseType, Interface, NamedType};
use crate::error::ParseError;
use crate::msg::{is_valid_package_name, parse_file};
use crate::rust::{sibling_path, Derives, Generator, TypePaths, UnknownType};
use crate::type_description::{event_message, ActionTypes};

/// Errors of [`Builder::generate`].
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    /// An interface file is malformed.
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// A package directory has no readable `package.xml` with a `<name>`.
    #[error("{path}: {reason}")]
    PackageXml {
        /// The `package.xml`.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A directory could not be listed.
    #[error("cannot list {path}")]
    ReadDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A type used by a generated type is found nowhere.
    #[error(transparent)]
    UnknownType(#[from] UnknownType),
    /// Two inputs define the same type.
    #[error("type '{0}' is defined twice among the inputs")]
    Duplicate(String),
    /// No output directory: neither [`Builder::out_dir`] nor `OUT_DIR` (set by cargo for build
    /// scripts).
    #[error("no output directory: call Builder::out_dir or run from a build script (OUT_DIR)")]
    NoOutDir,
    /// The generated source could not be written.
    #[error("cannot write {path}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

/// Generates Rust modules from ROS 2 interface files.
#[derive(Debug, Clone)]
#[must_use]
pub struct Builder {
    package_dirs: Vec<PathBuf>,
    files: Vec<(String, PathBuf)>,
    prefix_packages: Vec<String>,
    prefixes: Vec<PathBuf>,
    ament_prefix_path: bool,
    compiled_types: bool,
    out_dir: Option<PathBuf>,
    root_file: String,
    comments: bool,
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

/// What [`Builder::generate`] wrote.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The file to `include!`: one `pub mod <package>` per generated package.
    pub root: PathBuf,
    /// Each generated package and its file.
    pub packages: BTreeMap<String, PathBuf>,
    /// Every interface file read.
    pub inputs: Vec<PathBuf>,
    /// How many interfaces were generated.
    pub interfaces: usize,
}

impl Builder {
    /// A builder with no inputs; dependencies resolved from `AMENT_PREFIX_PATH` and the types
    /// compiled into horus-ros-msgs.
    pub fn new() -> Self {
        Self {
            package_dirs: Vec::new(),
            files: Vec::new(),
            prefix_packages: Vec::new(),
            prefixes: Vec::new(),
            ament_prefix_path: true,
            compiled_types: true,
            out_dir: None,
            root_file: "interfaces.rs".to_owned(),
            comments: true,
        }
    }

    /// Generates a package directory: a `package.xml` (its `<name>`) and `msg/`, `srv/`,
    /// `action/` with `.msg`/`.srv`/`.action` or `.idl` files.
    pub fn package_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.package_dirs.push(dir.into());
        self
    }

    /// Generates one interface file of `package` (`.msg`, `.srv`, `.action` or `.idl`).
    pub fn file(mut self, package: &str, path: impl Into<PathBuf>) -> Self {
        self.files.push((package.to_owned(), path.into()));
        self
    }

    /// Generates the package `name` found in an install prefix (`<prefix>/share/<name>`).
    pub fn prefix_package(mut self, name: &str) -> Self {
        self.prefix_packages.push(name.to_owned());
        self
    }

    /// Adds an install prefix searched for packages (as an entry of `AMENT_PREFIX_PATH`).
    pub fn prefix(mut self, dir: impl Into<PathBuf>) -> Self {
        self.prefixes.push(dir.into());
        self
    }

    /// Whether the prefixes of `AMENT_PREFIX_PATH` are searched (default: yes).
    pub fn ament_prefix_path(mut self, on: bool) -> Self {
        self.ament_prefix_path = on;
        self
    }

    /// Whether types compiled into horus-ros-msgs are used rather than generated again
    /// (default: yes, so a generated message holding a `std_msgs/Header` uses
    /// `horus_ros_msgs::std_msgs::msg::Header`).
    pub fn compiled_types(mut self, on: bool) -> Self {
        self.compiled_types = on;
        self
    }

    /// Whether the interface files' comments become doc comments (default: yes).
    pub fn comments(mut self, on: bool) -> Self {
        self.comments = on;
        self
    }

    /// Where to write (default: `OUT_DIR`).
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// The name of the file with every package's module (default `interfaces.rs`).
    pub fn root_file(mut self, name: &str) -> Self {
        name.clone_into(&mut self.root_file);
        self
    }

    /// The install prefixes searched, in order: [`prefix`](Self::prefix)es, then
    /// `AMENT_PREFIX_PATH`'s.
    fn index(&self) -> AmentIndex {
        let mut prefixes = self.prefixes.clone();
        if self.ament_prefix_path {
            prefixes.extend(AmentIndex::from_env().prefixes().iter().cloned());
        }
        AmentIndex::from_prefixes(prefixes)
    }

    /// Parses every input and what it needs, and writes one file per package plus the root file.
    pub fn generate(self) -> Result<Generated, GenerateError> {
        let in_build_script = std::env::var_os("OUT_DIR").is_some();
        let out_dir = match (&self.out_dir, std::env::var_os("OUT_DIR")) {
            (Some(d), _) => d.clone(),
            (None, Some(d)) => PathBuf::from(d),
            (None, None) => return Err(GenerateError::NoOutDir),
        };
        let index = self.index();
        let mut set = InterfaceSet::default();
        for dir in &self.package_dirs {
            let name = package_name(dir)?;
            set.add_package(&name, dir)?;
        }
        for (package, file) in &self.files {
            set.add(package, file)?;
        }
        for name in &self.prefix_packages {
            let dir = index.package_share(name).ok_or_else(|| UnknownType {
                missing: format!("{name}/*"),
                user: "Builder::prefix_package".to_owned(),
            })?;
            set.add_package(name, &dir)?;
        }

        // Pull in the packages of types found neither generated nor compiled.
        loop {
            let missing: BTreeSet<String> = set
                .used_types()
                .into_iter()
                .filter(|t| {
                    !(set.defines(t) || (self.compiled_types && compiled::path(t).is_some()))
                })
                .map(|t| t.package)
                .filter(|p| !set.packages.contains_key(p))
                .collect();
            if missing.is_empty() {
                break;
            }
            let mut added = false;
            for package in missing {
                if let Some(dir) = index.package_share(&package) {
                    set.add_package(&package, &dir)?;
                    added = true;
                }
            }
            if !added {
                break;
            }
        }

        let paths = Paths {
            set: &set,
            compiled_types: self.compiled_types,
            derives: RefCell::new(BTreeMap::new()),
        };
        std::fs::create_dir_all(&out_dir).map_err(|source| GenerateError::Write {
            path: out_dir.clone(),
            source,
        })?;
        let mut root = String::from(
            "// Generated by horus-ros-codegen: one module per ROS package. Do not edit.\n",
        );
        let mut packages = BTreeMap::new();
        let mut count = 0;
        for (package, interfaces) in &set.packages {
            count += interfaces.len();
            let source = Generator::new(&paths)
                .comments(self.comments)
                .package(interfaces)?;
            let file = out_dir.join(format!("{package}.rs"));
            write_if_changed(&file, &source)?;
            root.push_str(&format!(
                "\n/// The ROS package `{package}`.\npub mod {package} {{\n    include!(\"{package}.rs\");\n}}\n"
            ));
            packages.insert(package.clone(), file);
        }
        root.push_str(
            "\n/// Every generated package with its interfaces (ROS type name, type description).\n\
             pub const PACKAGES: &[(&str, &[(&str, ::horus_ros_msgs::DescribeFn)])] = &[\n",
        );
        for package in packages.keys() {
            root.push_str(&format!("    (\"{package}\", {package}::TYPES),\n"));
        }
        root.push_str("];\n");
        let root_path = out_dir.join(&self.root_file);
        write_if_changed(&root_path, &root)?;
        if in_build_script {
            for f in &set.inputs {
                println!("cargo:rerun-if-changed={}", f.display());
            }
            println!("cargo:rerun-if-env-changed=AMENT_PREFIX_PATH");
        }
        Ok(Generated {
            root: root_path,
            packages,
            inputs: set.inputs,
            interfaces: count,
        })
    }
}

/// Writes `text` unless the file already holds it (so cargo does not rebuild for nothing).
fn write_if_changed(path: &Path, text: &str) -> Result<(), GenerateError> {
    if std::fs::read_to_string(path).is_ok_and(|old| old == text) {
        return Ok(());
    }
    std::fs::write(path, text).map_err(|source| GenerateError::Write {
        path: path.to_owned(),
        source,
    })
}

/// The `<name>` of `dir/package.xml` (REP 149).
pub fn package_name(dir: &Path) -> Result<String, GenerateError> {
    let path = dir.join("package.xml");
    let fail = |reason: String| GenerateError::PackageXml {
        path: path.clone(),
        reason,
    };
    let text = std::fs::read_to_string(&path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let doc = roxmltree::Document::parse(&text).map_err(|e| fail(format!("not XML: {e}")))?;
    let name = doc
        .root_element()
        .children()
        .find(|n| n.has_tag_name("name"))
        .and_then(|n| n.text())
        .map(str::trim)
        .ok_or_else(|| fail("no <name> element in <package>".to_owned()))?;
    if !is_valid_package_name(name) {
        return Err(fail(format!("'{name}' is not a valid ROS package name")));
    }
    Ok(name.to_owned())
}

/// Parsed interfaces by package.
#[derive(Default)]
struct InterfaceSet {
    packages: BTreeMap<String, Vec<Interface>>,
    names: BTreeSet<String>,
    defined: BTreeMap<NamedType, crate::definition::Message>,
    inputs: Vec<PathBuf>,
}

impl InterfaceSet {
    /// Every interface file of a package directory: `.msg`/`.srv`/`.action`, or the `.idl` of an
    /// interface that has none of those (rosidl installs both).
    fn add_package(&mut self, package: &str, dir: &Path) -> Result<(), GenerateError> {
        self.packages.entry(package.to_owned()).or_default();
        for kind in ["msg", "srv", "action"] {
            let sub = dir.join(kind);
            if !sub.is_dir() {
                continue;
            }
            let entries = std::fs::read_dir(&sub).map_err(|source| GenerateError::ReadDir {
                path: sub.clone(),
                source,
            })?;
            let mut files: Vec<PathBuf> =
                entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
            files.sort();
            let ext = |p: &Path| p.extension().and_then(|e| e.to_str()).map(str::to_owned);
            for f in &files {
                match ext(f).as_deref() {
                    Some("msg" | "srv" | "action") => self.add(package, f)?,
                    Some("idl") => {
                        let has_source = ["msg", "srv", "action"]
                            .iter()
                            .any(|e| f.with_extension(e).is_file());
                        if !has_source {
                            self.add(package, f)?;
                        }
                    }
                    _ => {}
                }
            }
        }
        Ok(())
    }

    fn add(&mut self, package: &str, file: &Path) -> Result<(), GenerateError> {
        let interface = parse_file(package, file)?;
        let name = interface.name().to_string();
        if !self.names.insert(name.clone()) {
            return Err(GenerateError::Duplicate(name));
        }
        self.inputs.push(file.to_owned());
        self.defined.extend(
            messages(&interface)
                .into_iter()
                .map(|m| (m.name.clone(), m)),
        );
        self.packages
            .entry(interface.name().package.clone())
            .or_default()
            .push(interface);
        Ok(())
    }

    /// Whether a generated interface defines `t` (derived types included).
    fn defines(&self, t: &NamedType) -> bool {
        self.defined.contains_key(t)
    }

    /// Every message type a field of a generated type names.
    fn used_types(&self) -> BTreeSet<NamedType> {
        let mut out = BTreeSet::new();
        for interfaces in self.packages.values() {
            for i in interfaces {
                for m in messages(i) {
                    for f in &m.fields {
                        if let BaseType::Named(t) = &f.ty.base {
                            out.insert(t.clone());
                        }
                    }
                }
            }
        }
        out
    }
}

/// Every message an interface defines, derived ones included.
fn messages(i: &Interface) -> Vec<crate::definition::Message> {
    match i {
        Interface::Message(m) => vec![m.clone()],
        Interface::Service(s) => vec![s.request.clone(), s.response.clone(), event_message(s)],
        Interface::Action(a) => {
            let d = ActionTypes::of(a);
            vec![
                a.goal.clone(),
                a.result.clone(),
                a.feedback.clone(),
                d.send_goal.request.clone(),
                d.send_goal.response.clone(),
                event_message(&d.send_goal),
                d.get_result.request.clone(),
                d.get_result.response.clone(),
                event_message(&d.get_result),
                d.feedback_message,
            ]
        }
    }
}

/// Resolves types: generated beside, else compiled into horus-ros-msgs.
struct Paths<'a> {
    set: &'a InterfaceSet,
    compiled_types: bool,
    /// What each generated type may derive, worked out once (`None` while being worked out:
    /// a type nesting itself derives nothing more).
    derives: RefCell<BTreeMap<NamedType, Option<Derives>>>,
}

impl TypePaths for Paths<'_> {
    fn rust_path(&self, from: &NamedType, t: &NamedType) -> Option<String> {
        if self.set.defines(t) {
            return Some(sibling_path(from, t));
        }
        if self.compiled_types {
            return compiled::path(t);
        }
        None
    }

    fn derives(&self, t: &NamedType) -> Derives {
        if let Some(known) = self.derives.borrow().get(t) {
            return known.unwrap_or_default();
        }
        let Some(m) = self.set.defined.get(t) else {
            return Derives::default();
        };
        self.derives.borrow_mut().insert(t.clone(), None);
        let d = Derives::of(m, |n| self.derives(n));
        self.derives.borrow_mut().insert(t.clone(), Some(d));
        d
    }
}
