//! The Rust types horus-ros-codegen generates from the interface files of every package of the
//! Jazzy wheels (`interop_tests::jazzy`, built by build.rs) describe and hash exactly as Jazzy:
//! each interface's full type description (every type it defines or uses, with defaults) equals
//! the `type_description_msg` of the `.json` rosidl wrote beside it, and each type hash listed
//! there equals ours. No DDS.

#[test]
fn every_generated_interface_describes_and_hashes_as_jazzy() {
    interop_tests::require_jazzy_interfaces();
    #[cfg(jazzy_interfaces)]
    {
        use horus_ros_msgs::rihs::rihs01;
        use interop_tests::peers::wheels;
        use std::collections::BTreeSet;

        let mut interfaces = 0;
        let mut types = BTreeSet::new();
        let mut failures = Vec::new();
        for (package, table) in interop_tests::jazzy::PACKAGES {
            for (type_name, describe) in table.iter() {
                interfaces += 1;
                let ours = describe();
                let file = wheels::interface_file(type_name).expect("type name");
                let jazzy = wheels::read_json(&file).expect("wheels' json");
                let as_json = serde_json::to_value(&ours).expect("description as JSON");
                if as_json != jazzy["type_description_msg"] {
                    failures.push(format!("{package}: {type_name}: description differs\n ours:  {as_json}\n jazzy: {}", jazzy["type_description_msg"]));
                }
                // Every type in the description hashes as Jazzy hashes it.
                for t in std::iter::once(&ours.type_description)
                    .chain(&ours.referenced_type_descriptions)
                {
                    let sub = horus_ros_services::dynamic::sub_description(&ours, &t.type_name)
                        .expect("sub-description");
                    let expected = jazzy["type_hashes"]
                        .as_array()
                        .and_then(|h| h.iter().find(|h| h["type_name"] == t.type_name.as_str()))
                        .and_then(|h| h["hash_string"].as_str())
                        .map(str::to_owned);
                    match expected {
                        Some(e) if e == rihs01(&sub).to_string() => {}
                        other => failures.push(format!(
                            "{type_name}: {}: ours {}, jazzy {other:?}",
                            t.type_name,
                            rihs01(&sub)
                        )),
                    }
                    types.insert(t.type_name.clone());
                }
            }
        }
        assert!(
            failures.is_empty(),
            "{} differences:\n{}",
            failures.len(),
            failures.join("\n")
        );
        println!(
            "{} packages, {interfaces} generated interfaces, {} distinct types: descriptions and hashes equal Jazzy's",
            interop_tests::jazzy::PACKAGES.len(),
            types.len()
        );
        assert!(interfaces >= 199, "only {interfaces} interfaces generated");
    }
}
