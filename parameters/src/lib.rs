//! [`Parameters`]: a node's thread-safe parameter store, with rclcpp (jazzy, 28.1)
//! `NodeParameters` semantics (`rclcpp/src/rclcpp/node_interfaces/node_parameters.cpp`).
//!
//! Reasons and error texts are rclcpp's, so that `ros2 param set` prints what it prints for an
//! rclcpp node.
//!
//! A pure data structure (no DDS): horus-ros-services' `NodeServices` serves it as a node's
//! parameter services and publishes its changes on `/parameter_events`.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, MutexGuard};

use horus_ros_msgs::rcl_interfaces::msg::{
    ListParametersResult, Parameter, ParameterDescriptor, ParameterType, ParameterValue,
    SetParametersResult,
};
use horus_ros_msgs::rcl_interfaces::srv::ListParametersRequest;

/// The separator of parameter name components (`a.b.c`), as rclcpp.
const SEPARATOR: char = '.';

/// Why a parameter operation of [`Parameters`] failed. The texts are rclcpp's exception texts.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ParameterError {
    /// The parameter name is empty.
    #[error("parameter name must not be empty")]
    EmptyName,
    /// `declare` of a name already declared.
    #[error("parameter '{0}' has already been declared")]
    AlreadyDeclared(String),
    /// The parameter was not declared (and undeclared parameters are not allowed).
    #[error("parameter '{0}' has not been declared")]
    NotDeclared(String),
    /// The parameter is declared, statically typed and has no value yet.
    #[error("parameter '{0}' is not initialized")]
    Uninitialized(String),
    /// `declare` with a value of the wrong type, or a statically typed parameter without a value;
    /// `undeclare` of a statically typed parameter.
    #[error("parameter '{name}' has invalid type: {reason}")]
    InvalidType {
        /// The parameter.
        name: String,
        /// Why (rclcpp's text).
        reason: String,
    },
    /// `declare` with a value outside the descriptor's range.
    #[error("parameter '{name}' could not be set: {reason}")]
    InvalidValue {
        /// The parameter.
        name: String,
        /// Why (rclcpp's text, e.g. `Parameter {x} doesn't comply with integer range.`).
        reason: String,
    },
    /// `undeclare` of a read-only parameter.
    #[error("cannot undeclare parameter '{0}' because it is read-only")]
    ReadOnly(String),
    /// `set` was refused; the reason is the one a `set_parameters` service reply carries.
    #[error("{0}")]
    Rejected(String),
}

/// One declared parameter: its value and descriptor (`rclcpp::node_interfaces::ParameterInfo`).
#[derive(Debug, Clone, Default)]
struct ParameterInfo {
    value: ParameterValue,
    descriptor: ParameterDescriptor,
}

/// The parameters of one node, shared by the parameter services (horus-ros-services'
/// `NodeServices`) and the application. Cloning gives another handle to the same store.
#[derive(Debug, Clone, Default)]
pub struct Parameters {
    inner: Arc<Mutex<Store>>,
}

#[derive(Default)]
struct Store {
    /// Sorted by name, as rclcpp's `std::map` (list order).
    params: BTreeMap<String, ParameterInfo>,
    allow_undeclared: bool,
    /// Told of every change ([`Parameters::on_change`]), under the store's lock.
    listeners: Vec<ChangeListener>,
}

impl std::fmt::Debug for Store {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("params", &self.params)
            .field("allow_undeclared", &self.allow_undeclared)
            .field("listeners", &self.listeners.len())
            .finish()
    }
}

type ChangeListener = Box<dyn Fn(&ParameterChange) + Send + Sync>;

/// What one change did to the store, as rclcpp fills a `rcl_interfaces/msg/ParameterEvent`
/// (`node_parameters.cpp`): `declare` lists the parameter as new (no entry when declared
/// without a value); a successful `set_atomically` lists the implicitly declared parameters as
/// new, those set to `PARAMETER_NOT_SET` as deleted (with that value) and the others as
/// changed, each list in request order. `undeclare` tells nothing, as rclcpp publishes no event
/// for it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParameterChange {
    /// Parameters declared.
    pub new_parameters: Vec<Parameter>,
    /// Parameters whose value was set.
    pub changed_parameters: Vec<Parameter>,
    /// Parameters undeclared.
    pub deleted_parameters: Vec<Parameter>,
}

/// Why [`Parameters::set_atomically_result`] failed before producing a result: rclcpp's
/// `ParameterNotDeclaredException` (its text is
/// `parameter '<name>' cannot be set because it was not declared`), naming the parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotDeclaredForSet(pub String);

impl NotDeclaredForSet {
    /// rclcpp's exception text, which `~/set_parameters` returns as the reason.
    pub fn reason(&self) -> String {
        format!(
            "parameter '{}' cannot be set because it was not declared",
            self.0
        )
    }
}

impl Parameters {
    /// An empty store. With `allow_undeclared`, setting an undeclared parameter declares it
    /// (dynamically typed) and reading one gives `PARAMETER_NOT_SET`, as rclcpp's
    /// `allow_undeclared_parameters` node option.
    pub fn new(allow_undeclared: bool) -> Self {
        Self {
            inner: Arc::new(Mutex::new(Store {
                params: BTreeMap::new(),
                allow_undeclared,
                listeners: Vec::new(),
            })),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Store> {
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Calls `listener` after every change (see [`ParameterChange`]), in the order of the
    /// changes: it runs under the store's lock, so it must not use this store.
    pub fn on_change(&self, listener: impl Fn(&ParameterChange) + Send + Sync + 'static) {
        self.lock().listeners.push(Box::new(listener));
    }

    /// Whether undeclared parameters are allowed (see [`new`](Self::new)).
    pub fn allows_undeclared(&self) -> bool {
        self.lock().allow_undeclared
    }

    /// Declares `name` with an initial `value` and `descriptor`, as rclcpp's
    /// `declare_parameter(name, default_value, descriptor)`: unless `descriptor.dynamic_typing`,
    /// the parameter's type is `value`'s type (the descriptor's `type` is overwritten) and the
    /// value must be set; the value must comply with the descriptor's range. The descriptor's
    /// `name` is set to `name`. Returns the stored value.
    pub fn declare(
        &self,
        name: &str,
        value: ParameterValue,
        mut descriptor: ParameterDescriptor,
    ) -> Result<ParameterValue, ParameterError> {
        if name.is_empty() {
            return Err(ParameterError::EmptyName);
        }
        let value = normalize(value).map_err(|reason| ParameterError::InvalidType {
            name: name.to_owned(),
            reason,
        })?;
        let mut store = self.lock();
        if store.params.contains_key(name) {
            return Err(ParameterError::AlreadyDeclared(name.to_owned()));
        }
        if !descriptor.dynamic_typing {
            if value.r#type == ParameterType::PARAMETER_NOT_SET {
                return Err(ParameterError::InvalidType {
                    name: name.to_owned(),
                    reason: "cannot declare a statically typed parameter with an uninitialized \
                             value"
                        .to_owned(),
                });
            }
            descriptor.r#type = value.r#type;
        }
        let info = declare_common(name, value, descriptor).map_err(|reason| {
            if reason.starts_with("Wrong parameter type") {
                ParameterError::InvalidType {
                    name: name.to_owned(),
                    reason,
                }
            } else {
                ParameterError::InvalidValue {
                    name: name.to_owned(),
                    reason,
                }
            }
        })?;
        let stored = info.value.clone();
        store.params.insert(name.to_owned(), info);
        // rclcpp publishes an event for every declaration, listing the parameter only when it
        // got a value.
        let mut change = ParameterChange::default();
        if stored.r#type != ParameterType::PARAMETER_NOT_SET {
            change.new_parameters.push(Parameter {
                name: name.to_owned(),
                value: stored.clone(),
            });
        }
        store.notify(&change);
        Ok(stored)
    }

    /// Removes a declared parameter, as rclcpp's `undeclare_parameter`: read-only and statically
    /// typed parameters cannot be undeclared.
    pub fn undeclare(&self, name: &str) -> Result<(), ParameterError> {
        let mut store = self.lock();
        let info = store
            .params
            .get(name)
            .ok_or_else(|| ParameterError::NotDeclared(name.to_owned()))?;
        if info.descriptor.read_only {
            return Err(ParameterError::ReadOnly(name.to_owned()));
        }
        if !info.descriptor.dynamic_typing {
            return Err(ParameterError::InvalidType {
                name: name.to_owned(),
                reason: "cannot undeclare a statically typed parameter".to_owned(),
            });
        }
        store.params.remove(name);
        Ok(())
    }

    /// Whether `name` is declared.
    pub fn has(&self, name: &str) -> bool {
        self.lock().params.contains_key(name)
    }

    /// The value of `name`, as rclcpp's `get_parameter`: an undeclared name is
    /// [`NotDeclared`](ParameterError::NotDeclared) (or `PARAMETER_NOT_SET` when undeclared
    /// parameters are allowed); a statically typed parameter without a value is
    /// [`Uninitialized`](ParameterError::Uninitialized).
    pub fn get(&self, name: &str) -> Result<ParameterValue, ParameterError> {
        self.lock().get(name)
    }

    /// The descriptor of `name` (`describe_parameters` for one name).
    pub fn describe(&self, name: &str) -> Result<ParameterDescriptor, ParameterError> {
        self.lock().describe(name)
    }

    /// The type (`ParameterType::PARAMETER_*`) of `name`'s current value.
    pub fn get_type(&self, name: &str) -> Result<u8, ParameterError> {
        self.lock().get_type(name)
    }

    /// Sets one parameter, as rclcpp's `set_parameter`: it must be declared (unless undeclared
    /// parameters are allowed), not read-only, of the declared type unless dynamically typed,
    /// and in range. Setting a dynamically typed parameter to `PARAMETER_NOT_SET` undeclares it.
    /// A refusal is [`Rejected`](ParameterError::Rejected) with rclcpp's reason.
    pub fn set(&self, name: &str, value: ParameterValue) -> Result<(), ParameterError> {
        self.set_atomically(&[Parameter {
            name: name.to_owned(),
            value,
        }])
    }

    /// Sets several parameters, all or none (rclcpp's `set_parameters_atomically`).
    pub fn set_atomically(&self, parameters: &[Parameter]) -> Result<(), ParameterError> {
        match self.set_atomically_result(parameters) {
            Ok(result) if result.successful => Ok(()),
            Ok(result) => Err(ParameterError::Rejected(result.reason)),
            Err(e) => Err(ParameterError::Rejected(e.reason())),
        }
    }

    /// Names of all declared parameters, sorted.
    pub fn names(&self) -> Vec<String> {
        self.lock().params.keys().cloned().collect()
    }

    /// Lists parameters as the `~/list_parameters` service (rclcpp's `list_parameters`): with no
    /// prefixes and depth [`DEPTH_RECURSIVE`](ListParametersRequest::DEPTH_RECURSIVE) (0) every
    /// name; with no prefixes, names with fewer than `depth` dots; with prefixes, names equal to
    /// a prefix or under `prefix.` with fewer than `depth` dots below it (any with depth 0).
    /// `prefixes` of the result are the distinct parts before the last dot of the names listed.
    pub fn list(&self, prefixes: &[String], depth: u64) -> ListParametersResult {
        self.lock().list(prefixes, depth)
    }

    /// Every declared parameter with its value and descriptor, sorted by name.
    pub fn snapshot(&self) -> Vec<(Parameter, ParameterDescriptor)> {
        self.lock()
            .params
            .iter()
            .map(|(name, info)| {
                (
                    Parameter {
                        name: name.clone(),
                        value: info.value.clone(),
                    },
                    info.descriptor.clone(),
                )
            })
            .collect()
    }

    /// rclcpp's `set_parameters_atomically`: a result (`successful`, `reason`), or the
    /// not-declared "exception".
    pub fn set_atomically_result(
        &self,
        parameters: &[Parameter],
    ) -> Result<SetParametersResult, NotDeclaredForSet> {
        self.lock().set_atomically(parameters)
    }

    /// `~/get_parameters`: values in request order; an empty list when any name is undeclared
    /// (or statically typed and uninitialized), as rclcpp's service.
    pub fn get_many(&self, names: &[String]) -> Vec<ParameterValue> {
        let store = self.lock();
        names
            .iter()
            .map(|n| store.get(n))
            .collect::<Result<Vec<_>, _>>()
            .unwrap_or_default()
    }

    /// `~/get_parameter_types`: types in request order, empty when any name is undeclared.
    pub fn types_many(&self, names: &[String]) -> Vec<u8> {
        let store = self.lock();
        names
            .iter()
            .map(|n| store.get_type(n))
            .collect::<Result<Vec<_>, _>>()
            .unwrap_or_default()
    }

    /// `~/describe_parameters`: descriptors in request order, empty when any name is undeclared.
    pub fn describe_many(&self, names: &[String]) -> Vec<ParameterDescriptor> {
        let store = self.lock();
        names
            .iter()
            .map(|n| store.describe(n))
            .collect::<Result<Vec<_>, _>>()
            .unwrap_or_default()
    }
}

impl Store {
    fn notify(&self, change: &ParameterChange) {
        for listener in &self.listeners {
            listener(change);
        }
    }

    fn get(&self, name: &str) -> Result<ParameterValue, ParameterError> {
        match self.params.get(name) {
            Some(info)
                if info.value.r#type != ParameterType::PARAMETER_NOT_SET
                    || info.descriptor.dynamic_typing =>
            {
                Ok(info.value.clone())
            }
            Some(_) => Err(ParameterError::Uninitialized(name.to_owned())),
            None if self.allow_undeclared => Ok(ParameterValue::default()),
            None => Err(ParameterError::NotDeclared(name.to_owned())),
        }
    }

    fn get_type(&self, name: &str) -> Result<u8, ParameterError> {
        match self.params.get(name) {
            Some(info) => Ok(info.value.r#type),
            None if self.allow_undeclared => Ok(ParameterType::PARAMETER_NOT_SET),
            None => Err(ParameterError::NotDeclared(name.to_owned())),
        }
    }

    fn describe(&self, name: &str) -> Result<ParameterDescriptor, ParameterError> {
        match self.params.get(name) {
            Some(info) => Ok(info.descriptor.clone()),
            None if self.allow_undeclared => Ok(ParameterDescriptor {
                name: name.to_owned(),
                ..ParameterDescriptor::default()
            }),
            None => Err(ParameterError::NotDeclared(name.to_owned())),
        }
    }

    fn list(&self, prefixes: &[String], depth: u64) -> ListParametersResult {
        let separators_less_than_depth = |s: &str| (s.matches(SEPARATOR).count() as u64) < depth;
        let recursive = prefixes.is_empty() && depth == ListParametersRequest::DEPTH_RECURSIVE;
        let mut result = ListParametersResult::default();
        for name in self.params.keys() {
            if !recursive {
                let get_all = prefixes.is_empty() && separators_less_than_depth(name);
                if !get_all {
                    let matches = prefixes.iter().any(|prefix| {
                        if name == prefix {
                            return true;
                        }
                        match name
                            .strip_prefix(prefix.as_str())
                            .and_then(|rest| rest.strip_prefix(SEPARATOR))
                        {
                            Some(rest) => {
                                depth == ListParametersRequest::DEPTH_RECURSIVE
                                    || separators_less_than_depth(rest)
                            }
                            None => false,
                        }
                    });
                    if !matches {
                        continue;
                    }
                }
            }
            result.names.push(name.clone());
            if let Some((prefix, _)) = name.rsplit_once(SEPARATOR) {
                if !result.prefixes.iter().any(|p| p == prefix) {
                    result.prefixes.push(prefix.to_owned());
                }
            }
        }
        result
    }

    fn set_atomically(
        &mut self,
        parameters: &[Parameter],
    ) -> Result<SetParametersResult, NotDeclaredForSet> {
        if parameters.is_empty() {
            // rclcpp (jazzy) checks the list after its pre-set callbacks; with none, an empty
            // request gets this reason.
            return Ok(failure(
                "parameter list cannot be empty, this might be due to \
                 pre_set_parameters_callback modifying the original parameters list.",
            ));
        }
        let mut to_set = Vec::with_capacity(parameters.len());
        for p in parameters {
            match normalize(p.value.clone()) {
                Ok(value) => to_set.push(Parameter {
                    name: p.name.clone(),
                    value,
                }),
                Err(reason) => return Ok(failure(reason)),
            }
        }

        // Declared? Read-only?
        let mut to_declare = Vec::new();
        for p in &to_set {
            if p.name.is_empty() {
                return Ok(failure("parameter name must not be empty"));
            }
            match self.params.get(&p.name) {
                None if self.allow_undeclared => to_declare.push(p),
                None => return Err(NotDeclaredForSet(p.name.clone())),
                Some(info) if info.descriptor.read_only => {
                    return Ok(failure(format!(
                        "parameter '{}' cannot be set because it is read-only",
                        p.name
                    )));
                }
                Some(_) => {}
            }
        }

        // Implicit declarations (dynamically typed), staged.
        let mut staged = BTreeMap::new();
        for p in to_declare {
            let descriptor = ParameterDescriptor {
                dynamic_typing: true,
                ..ParameterDescriptor::default()
            };
            match declare_common(&p.name, p.value.clone(), descriptor) {
                Ok(info) => {
                    staged.insert(p.name.clone(), info);
                }
                Err(reason) => return Ok(failure(reason)),
            }
        }

        // Setting a dynamically typed parameter to NOT_SET undeclares it.
        let mut to_undeclare = Vec::new();
        for p in &to_set {
            if p.value.r#type != ParameterType::PARAMETER_NOT_SET {
                continue;
            }
            if let Some(info) = self.params.get(&p.name) {
                if info.value.r#type != ParameterType::PARAMETER_NOT_SET {
                    if !info.descriptor.dynamic_typing {
                        return Ok(failure("cannot undeclare a statically typed parameter"));
                    }
                    to_undeclare.push(p.name.clone());
                }
            }
        }

        // Check every value against its descriptor, then set them all.
        for p in &to_set {
            let mut descriptor = match self.params.get(&p.name) {
                Some(info) => info.descriptor.clone(),
                None => ParameterDescriptor {
                    dynamic_typing: true,
                    ..ParameterDescriptor::default()
                },
            };
            if descriptor.name.is_empty() {
                descriptor.name = p.name.clone();
            }
            if let Err(reason) = check_value(&p.name, &descriptor, &p.value) {
                return Ok(failure(reason));
            }
        }
        let mut change = ParameterChange::default();
        for p in &to_set {
            if staged.contains_key(&p.name) {
                change.new_parameters.push(p.clone());
            } else if to_undeclare.contains(&p.name) {
                change.deleted_parameters.push(p.clone());
            } else {
                change.changed_parameters.push(p.clone());
            }
        }
        for p in to_set {
            let info = self.params.entry(p.name.clone()).or_default();
            info.descriptor.name = p.name;
            info.descriptor.r#type = p.value.r#type;
            info.value = p.value;
        }
        for (name, info) in staged {
            self.params.insert(name, info);
        }
        for name in to_undeclare {
            self.params.remove(&name);
        }
        self.notify(&change);
        Ok(SetParametersResult {
            successful: true,
            reason: String::new(),
        })
    }
}

/// rclcpp's `__declare_parameter_common` without overrides and callbacks: the stored info, or
/// the reason the initial value was refused.
fn declare_common(
    name: &str,
    value: ParameterValue,
    mut descriptor: ParameterDescriptor,
) -> Result<ParameterInfo, String> {
    descriptor.name = name.to_owned();
    if value.r#type == ParameterType::PARAMETER_NOT_SET {
        if descriptor.dynamic_typing {
            descriptor.r#type = ParameterType::PARAMETER_NOT_SET;
        }
        return Ok(ParameterInfo { value, descriptor });
    }
    check_value(name, &descriptor, &value)?;
    descriptor.r#type = value.r#type;
    Ok(ParameterInfo { value, descriptor })
}

fn failure(reason: impl Into<String>) -> SetParametersResult {
    SetParametersResult {
        successful: false,
        reason: reason.into(),
    }
}

/// rclcpp's `__check_parameters` for one parameter: type (unless dynamically typed), then range.
fn check_value(
    name: &str,
    descriptor: &ParameterDescriptor,
    value: &ParameterValue,
) -> Result<(), String> {
    if !descriptor.dynamic_typing && descriptor.r#type != value.r#type {
        return Err(format!(
            "Wrong parameter type, parameter {{{name}}} is of type {{{}}}, setting it to {{{}}} \
             is not allowed.",
            type_name(descriptor.r#type),
            type_name(value.r#type)
        ));
    }
    check_range(descriptor, value)
}

/// rclcpp's `__check_parameter_value_in_range`.
fn check_range(descriptor: &ParameterDescriptor, value: &ParameterValue) -> Result<(), String> {
    let reason = |kind: &str| {
        format!(
            "Parameter {{{}}} doesn't comply with {kind} range.",
            descriptor.name
        )
    };
    if let (Some(range), ParameterType::PARAMETER_INTEGER) =
        (descriptor.integer_range.first(), value.r#type)
    {
        let v = value.integer_value;
        if v == range.from_value || v == range.to_value {
            return Ok(());
        }
        if v < range.from_value || v > range.to_value {
            return Err(reason("integer"));
        }
        if range.step == 0
            || (i128::from(v) - i128::from(range.from_value)) % i128::from(range.step) == 0
        {
            return Ok(());
        }
        return Err(reason("integer"));
    }
    if let (Some(range), ParameterType::PARAMETER_DOUBLE) =
        (descriptor.floating_point_range.first(), value.r#type)
    {
        let v = value.double_value;
        if doubles_equal(v, range.from_value) || doubles_equal(v, range.to_value) {
            return Ok(());
        }
        if v < range.from_value || v > range.to_value {
            return Err(reason("floating point"));
        }
        if range.step == 0.0 {
            return Ok(());
        }
        let rounded = ((v - range.from_value) / range.step).round();
        if doubles_equal(v, range.from_value + rounded * range.step) {
            return Ok(());
        }
        return Err(reason("floating point"));
    }
    Ok(())
}

/// rclcpp's `__are_doubles_equal` with `ulp = 100`.
fn doubles_equal(x: f64, y: f64) -> bool {
    (x - y).abs() <= f64::EPSILON * (x + y).abs() * 100.0
}

/// rclcpp's `to_string(ParameterType)`.
pub fn type_name(t: u8) -> &'static str {
    match t {
        ParameterType::PARAMETER_NOT_SET => "not set",
        ParameterType::PARAMETER_BOOL => "bool",
        ParameterType::PARAMETER_INTEGER => "integer",
        ParameterType::PARAMETER_DOUBLE => "double",
        ParameterType::PARAMETER_STRING => "string",
        ParameterType::PARAMETER_BYTE_ARRAY => "byte_array",
        ParameterType::PARAMETER_BOOL_ARRAY => "bool_array",
        ParameterType::PARAMETER_INTEGER_ARRAY => "integer_array",
        ParameterType::PARAMETER_DOUBLE_ARRAY => "double_array",
        ParameterType::PARAMETER_STRING_ARRAY => "string_array",
        _ => "unknown type",
    }
}

/// Keeps only the field `type` selects (rclcpp's `ParameterValue` from a message); an unknown
/// type is refused with rclcpp's text.
fn normalize(v: ParameterValue) -> Result<ParameterValue, String> {
    let mut out = ParameterValue {
        r#type: v.r#type,
        ..ParameterValue::default()
    };
    match v.r#type {
        ParameterType::PARAMETER_NOT_SET => {}
        ParameterType::PARAMETER_BOOL => out.bool_value = v.bool_value,
        ParameterType::PARAMETER_INTEGER => out.integer_value = v.integer_value,
        ParameterType::PARAMETER_DOUBLE => out.double_value = v.double_value,
        ParameterType::PARAMETER_STRING => out.string_value = v.string_value,
        ParameterType::PARAMETER_BYTE_ARRAY => out.byte_array_value = v.byte_array_value,
        ParameterType::PARAMETER_BOOL_ARRAY => out.bool_array_value = v.bool_array_value,
        ParameterType::PARAMETER_INTEGER_ARRAY => out.integer_array_value = v.integer_array_value,
        ParameterType::PARAMETER_DOUBLE_ARRAY => out.double_array_value = v.double_array_value,
        ParameterType::PARAMETER_STRING_ARRAY => out.string_array_value = v.string_array_value,
        other => return Err(format!("Unknown type: {other}")),
    }
    Ok(out)
}

/// Constructors for [`ParameterValue`]s of each type (the message has one field per type and a
/// `type` tag).
pub trait ParameterValueExt: Sized {
    /// `PARAMETER_NOT_SET`.
    fn not_set() -> Self;
    /// `PARAMETER_BOOL`.
    fn from_bool(v: bool) -> Self;
    /// `PARAMETER_INTEGER`.
    fn from_integer(v: i64) -> Self;
    /// `PARAMETER_DOUBLE`.
    fn from_double(v: f64) -> Self;
    /// `PARAMETER_STRING`.
    fn from_string(v: impl Into<String>) -> Self;
    /// `PARAMETER_BYTE_ARRAY`.
    fn from_bytes(v: &[u8]) -> Self;
    /// `PARAMETER_BOOL_ARRAY`.
    fn from_bool_array(v: Vec<bool>) -> Self;
    /// `PARAMETER_INTEGER_ARRAY`.
    fn from_integer_array(v: Vec<i64>) -> Self;
    /// `PARAMETER_DOUBLE_ARRAY`.
    fn from_double_array(v: Vec<f64>) -> Self;
    /// `PARAMETER_STRING_ARRAY`.
    fn from_string_array(v: Vec<String>) -> Self;
    /// rclcpp's name of this value's type (`"integer"`, `"not set"`, …).
    fn type_name(&self) -> &'static str;
}

impl ParameterValueExt for ParameterValue {
    fn not_set() -> Self {
        Self::default()
    }
    fn from_bool(v: bool) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_BOOL,
            bool_value: v,
            ..Self::default()
        }
    }
    fn from_integer(v: i64) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_INTEGER,
            integer_value: v,
            ..Self::default()
        }
    }
    fn from_double(v: f64) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_DOUBLE,
            double_value: v,
            ..Self::default()
        }
    }
    fn from_string(v: impl Into<String>) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_STRING,
            string_value: v.into(),
            ..Self::default()
        }
    }
    fn from_bytes(v: &[u8]) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_BYTE_ARRAY,
            byte_array_value: v.iter().map(|b| (*b).into()).collect(),
            ..Self::default()
        }
    }
    fn from_bool_array(v: Vec<bool>) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_BOOL_ARRAY,
            bool_array_value: v,
            ..Self::default()
        }
    }
    fn from_integer_array(v: Vec<i64>) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_INTEGER_ARRAY,
            integer_array_value: v,
            ..Self::default()
        }
    }
    fn from_double_array(v: Vec<f64>) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_DOUBLE_ARRAY,
            double_array_value: v,
            ..Self::default()
        }
    }
    fn from_string_array(v: Vec<String>) -> Self {
        Self {
            r#type: ParameterType::PARAMETER_STRING_ARRAY,
            string_array_value: v,
            ..Self::default()
        }
    }
    fn type_name(&self) -> &'static str {
        type_name(self.r#type)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use horus_ros_msgs::rcl_interfaces::msg::IntegerRange;

    fn store() -> Parameters {
        let p = Parameters::new(false);
        for name in ["a", "a.b", "a.b.c", "a.x", "b.c", "z"] {
            p.declare(
                name,
                ParameterValue::from_integer(1),
                ParameterDescriptor::default(),
            )
            .expect("declare");
        }
        p
    }

    #[test]
    fn list_follows_rclcpp_prefix_and_depth_rules() {
        let p = store();
        let all = p.list(&[], 0);
        assert_eq!(all.names, ["a", "a.b", "a.b.c", "a.x", "b.c", "z"]);
        assert_eq!(all.prefixes, ["a", "a.b", "b"]);
        assert_eq!(p.list(&[], 1).names, ["a", "z"]);
        assert_eq!(p.list(&[], 2).names, ["a", "a.b", "a.x", "b.c", "z"]);
        let a = ["a".to_owned()];
        assert_eq!(p.list(&a, 0).names, ["a", "a.b", "a.b.c", "a.x"]);
        assert_eq!(p.list(&a, 1).names, ["a", "a.b", "a.x"]);
        assert_eq!(p.list(&["a.b".to_owned()], 1).names, ["a.b", "a.b.c"]);
        assert!(p.list(&["q".to_owned()], 0).names.is_empty());
    }

    #[test]
    fn declare_set_and_undeclare_follow_rclcpp() {
        let p = Parameters::new(false);
        assert_eq!(
            p.declare("", ParameterValue::from_bool(true), Default::default()),
            Err(ParameterError::EmptyName)
        );
        let err = p
            .declare("n", ParameterValue::not_set(), Default::default())
            .expect_err("static without value");
        assert!(matches!(err, ParameterError::InvalidType { .. }), "{err}");
        p.declare(
            "n",
            ParameterValue::from_integer(4),
            ParameterDescriptor {
                integer_range: vec![IntegerRange {
                    from_value: 0,
                    to_value: 10,
                    step: 2,
                }],
                ..Default::default()
            },
        )
        .expect("declare n");
        assert_eq!(
            p.declare("n", ParameterValue::from_integer(1), Default::default()),
            Err(ParameterError::AlreadyDeclared("n".into()))
        );
        assert_eq!(p.set("n", ParameterValue::from_integer(6)), Ok(()));
        assert_eq!(
            p.set("n", ParameterValue::from_integer(5)),
            Err(ParameterError::Rejected(
                "Parameter {n} doesn't comply with integer range.".into()
            ))
        );
        assert_eq!(
            p.set("n", ParameterValue::from_double(1.0)),
            Err(ParameterError::Rejected(
                "Wrong parameter type, parameter {n} is of type {integer}, setting it to \
                 {double} is not allowed."
                    .into()
            ))
        );
        assert_eq!(
            p.set("nope", ParameterValue::from_double(1.0)),
            Err(ParameterError::Rejected(
                "parameter 'nope' cannot be set because it was not declared".into()
            ))
        );
        assert_eq!(p.get("n"), Ok(ParameterValue::from_integer(6)));
        assert!(matches!(
            p.undeclare("n"),
            Err(ParameterError::InvalidType { .. })
        ));
        let dynamic = ParameterDescriptor {
            dynamic_typing: true,
            ..Default::default()
        };
        p.declare("d", ParameterValue::from_bool(true), dynamic)
            .expect("declare d");
        assert_eq!(p.set("d", ParameterValue::from_string("x")), Ok(()));
        assert_eq!(p.get_type("d"), Ok(ParameterType::PARAMETER_STRING));
        // NOT_SET undeclares a dynamically typed parameter.
        assert_eq!(p.set("d", ParameterValue::not_set()), Ok(()));
        assert!(!p.has("d"));
    }

    #[test]
    fn undeclared_parameters_when_allowed() {
        let p = Parameters::new(true);
        assert_eq!(p.get("x"), Ok(ParameterValue::not_set()));
        assert_eq!(p.set("x", ParameterValue::from_integer(3)), Ok(()));
        let d = p.describe("x").expect("declared implicitly");
        assert!(d.dynamic_typing);
        assert_eq!(d.r#type, ParameterType::PARAMETER_INTEGER);
        assert_eq!(p.set("x", ParameterValue::from_bool(false)), Ok(()));
    }
}
