//! Every RIHS01 type hash horus-ros computes equals the one the ROS 2 Jazzy wheels ship
//! (`<venv>/share/<pkg>/{msg,srv,action}/<Name>.json`, written by
//! rosidl_generator_type_description when the packages were built): the hash of each type
//! compiled into horus-ros-msgs (messages, services with their request, response and event), and
//! the hash our REP-2011 code computes from each type description the wheels ship — every type
//! of every installed package (test_msgs' arrays, bounded and nested sequences, defaults,
//! constants, actions…). No DDS.

use horus_ros_msgs::{
    rcl_interfaces, std_srvs, type_description_interfaces, Message, Service, TypeDescription,
};
use horus_ros_services::dynamic::sub_description;
use interop_tests::peers::wheels;

/// `(type name, our RIHS01 string)` of each listed message type.
macro_rules! messages {
    ($($t:ty),* $(,)?) => {
        vec![$((<$t as Message>::TYPE_NAME.to_owned(), <$t as Message>::type_hash().to_string())),*]
    };
}

/// `(type name, our RIHS01 string)` of each listed service type, its request, response and
/// event.
macro_rules! services {
    ($($t:ty),* $(,)?) => {{
        let mut v = Vec::new();
        $(
            let name = <$t as Service>::TYPE_NAME;
            v.push((name.to_owned(), <$t as Service>::type_hash().to_string()));
            v.push((
                format!("{name}_Request"),
                <<$t as Service>::Request as Message>::type_hash().to_string(),
            ));
            v.push((
                format!("{name}_Response"),
                <<$t as Service>::Response as Message>::type_hash().to_string(),
            ));
            v.push((format!("{name}_Event"), <$t as Service>::event_type_hash().to_string()));
        )*
        v
    }};
}

#[test]
fn every_compiled_type_hashes_as_the_wheels() {
    let mut ours = interop_tests::compiled_message_types!(messages);
    ours.extend(services![
        std_srvs::srv::Empty,
        std_srvs::srv::Trigger,
        std_srvs::srv::SetBool,
        rcl_interfaces::srv::ListParameters,
        rcl_interfaces::srv::GetParameters,
        rcl_interfaces::srv::GetParameterTypes,
        rcl_interfaces::srv::SetParameters,
        rcl_interfaces::srv::SetParametersAtomically,
        rcl_interfaces::srv::DescribeParameters,
        type_description_interfaces::srv::GetTypeDescription,
    ]);
    let differing: Vec<String> = ours
        .iter()
        .filter_map(|(name, hash)| {
            let theirs = wheels::wheel_hash(name);
            (theirs.as_ref() != Ok(hash)).then(|| format!("{name}: ours {hash}, wheels {theirs:?}"))
        })
        .collect();
    assert!(differing.is_empty(), "{differing:#?}");
}

/// Every interface compiled into horus-ros-msgs (`INTERFACES`) has Jazzy's full description,
/// defaults included — but `example_interfaces`, which the wheels do not ship (its hashes are
/// checked in msgs' own tests).
#[test]
fn every_compiled_interface_describes_as_the_wheels() {
    let mut compared = 0;
    let mut differing = Vec::new();
    for (package, interfaces) in horus_ros_msgs::INTERFACES {
        if *package == "example_interfaces" {
            continue;
        }
        for (name, describe) in interfaces.iter() {
            let file = wheels::interface_file(name).unwrap_or_else(|e| panic!("{e}"));
            let json = wheels::read_json(&file).unwrap_or_else(|e| panic!("{e}"));
            let ours = serde_json::to_value(describe()).expect("description as JSON");
            if ours != json["type_description_msg"] {
                differing.push(format!(
                    "{name}:\n ours   {ours}\n wheels {}",
                    json["type_description_msg"]
                ));
            }
            compared += 1;
        }
    }
    assert!(differing.is_empty(), "{}", differing.join("\n"));
    assert!(compared > 100, "only {compared} interfaces");
    eprintln!("{compared} compiled interfaces describe as the wheels");
}

#[test]
fn every_description_the_wheels_ship_hashes_as_they_say() {
    let files = wheels::interface_files().unwrap_or_else(|e| panic!("{e}"));
    let mut compared = 0;
    let mut differing = Vec::new();
    for file in &files {
        let json = wheels::read_json(file).unwrap_or_else(|e| panic!("{e}"));
        let description: TypeDescription =
            serde_json::from_value(json["type_description_msg"].clone())
                .unwrap_or_else(|e| panic!("{}: type_description_msg: {e}", file.display()));
        for entry in json["type_hashes"].as_array().into_iter().flatten() {
            let (Some(name), Some(theirs)) =
                (entry["type_name"].as_str(), entry["hash_string"].as_str())
            else {
                panic!(
                    "{}: a type_hashes entry without name or hash",
                    file.display()
                );
            };
            let ours = sub_description(&description, name)
                .unwrap_or_else(|e| panic!("{}: {name}: {e}", file.display()))
                .compute_type_hash()
                .to_string();
            if ours != theirs {
                differing.push(format!("{name}: ours {ours}, wheels {theirs}"));
            }
            compared += 1;
        }
    }
    assert!(differing.is_empty(), "{differing:#?}");
    // std_msgs, std_srvs, test_msgs, rcl_interfaces, … : hundreds of types.
    assert!(
        files.len() > 150 && compared > 500,
        "only {} files, {compared} types",
        files.len()
    );
    eprintln!("{compared} types of {} interfaces", files.len());
}
