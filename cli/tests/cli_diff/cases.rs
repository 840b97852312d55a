//! The cases: every verb horus-ros shares with ros2cli 0.32.2, with its options' edge cases and
//! its errors, against the graph of `peers/jazzy_live_graph.py`. Each case's normalisation
//! (what depends on timing) is named beside it; a case without one is compared as printed.
//!
//! Order matters: the graph queries come first, before any case whose command creates
//! endpoints (a subscription, a publisher, a client): an endpoint of a command that has
//! exited can stay in a DDS graph for a while (rustdds' disposes are ignored by Fast DDS:
//! README, "What the rustdds backend cannot do"), which would change the counts the queries
//! print. Later cases only name topics and services that exist anyway.

use std::path::Path;

use super::{Case, Known, Norm};

/// The words of a command line as a POSIX shell splits it: on spaces, except inside single
/// quotes, which are removed (`param set /n name 'new value'`); `\\` outside them escapes the
/// next character.
fn words(line: &str) -> Vec<String> {
    let (mut out, mut word, mut quoted, mut started) = (Vec::new(), String::new(), false, false);
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            '\\' if !quoted => {
                word.extend(chars.next());
                started = true;
            }
            '\'' => {
                quoted = !quoted;
                started = true;
            }
            ' ' if !quoted => {
                if started {
                    out.push(std::mem::take(&mut word));
                    started = false;
                }
            }
            c => {
                word.push(c);
                started = true;
            }
        }
    }
    if started {
        out.push(word);
    }
    out
}

/// A case of the command line `line` (both tools get its words), compared as printed.
fn case(line: &str) -> Case {
    Case {
        args: words(line),
        norms: Vec::new(),
        stream: None,
        stdin: None,
        setup: Vec::new(),
        teardown: Vec::new(),
        horus_env_remove: Vec::new(),
        known: None,
        alone: false,
    }
}

impl Case {
    fn norm(mut self, norms: &[Norm]) -> Self {
        self.norms.extend_from_slice(norms);
        self
    }

    fn stream(mut self, lines: usize) -> Self {
        self.stream = Some(lines);
        self
    }

    fn stdin(mut self, text: &str) -> Self {
        self.stdin = Some(text.to_owned());
        self
    }

    fn around(mut self, setup: &[&str], teardown: &[&str]) -> Self {
        self.setup = setup.iter().map(|c| (*c).to_owned()).collect();
        self.teardown = teardown.iter().map(|c| (*c).to_owned()).collect();
        self
    }

    fn horus_without(mut self, var: &'static str) -> Self {
        self.horus_env_remove.push(var);
        self
    }

    fn alone(mut self) -> Self {
        self.alone = true;
        self
    }

    fn known(mut self, known: Known) -> Self {
        self.known = Some(known);
        self
    }
}

/// The peer's lifecycle node moved by `transition` (`peers/jazzy_live_graph.py`).
fn lifecycle(transition: &str) -> String {
    format!(r#"{{"lifecycle": "{transition}"}}"#)
}

/// Parameter files `param load` reads, written into `dir`; their paths.
struct Files {
    wildcard: String,
    only_wildcard: String,
    dump: String,
    other_node: String,
    bad_yaml: String,
    missing: String,
}

fn files(dir: &Path) -> Files {
    std::fs::create_dir_all(dir).expect("the cases' directory");
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("a parameter file");
        path.to_string_lossy().into_owned()
    };
    Files {
        // Wildcard and node entries, a nested name, a leading-dot float, a mixed list.
        wildcard: write(
            "wildcard.yaml",
            "/**:\n  ros__parameters:\n    count: 15\n    name: from wildcard\n\
             /param_node:\n  ros__parameters:\n    count: 25\n    nested:\n      depth: 4\n\
             \x20     deeper: {label: '5'}\n    ratio: .5\n    words: [a, 'true', 3]\n",
        ),
        only_wildcard: write("only.yaml", "/**:\n  ros__parameters:\n    count: 35\n"),
        // What `param dump /param_node` prints for the peer's values: every type, the
        // read-only parameter (refused), and `1.0e-05`, which rclpy reads back as a string.
        dump: write(
            "dump.yaml",
            "/param_node:\n  ros__parameters:\n    count: 20\n    doubles:\n    - 1.5\n    - -2.0\n\
             \x20   - 1.0e-05\n    dynamic: any\n    fixed: 7\n    flag: true\n    flags:\n    - true\n\
             \x20   - false\n    name: hello world\n    nested:\n      deeper:\n        label: x\n\
             \x20     depth: 2\n    numbers:\n    - 1\n    - 2\n    - 3\n    quoted: 'true'\n\
             \x20   ratio: 0.25\n    use_sim_time: false\n    words:\n    - a\n    - b c\n    - '5'\n",
        ),
        other_node: write("other.yaml", "/other:\n  ros__parameters:\n    x: 1\n"),
        bad_yaml: write("bad.yaml", "/param_node:\n  ros__parameters:\n    a: [1,\n"),
        missing: dir.join("missing.yaml").to_string_lossy().into_owned(),
    }
}

/// Every case, in the order they run; `dir` holds the parameter files.
pub fn all(dir: &Path) -> Vec<Case> {
    let f = files(dir);
    let mut cases = graph_queries();
    cases.extend(interfaces());
    cases.extend(topics());
    cases.extend(services());
    cases.extend(params(&f));
    cases.extend(actions());
    cases.extend(lifecycles());
    cases
}

/// Node, topic, service, action and lifecycle-node queries: the graph as each tool sees it.
fn graph_queries() -> Vec<Case> {
    let mut cases: Vec<Case> = [
        "node list",
        "node list -a",
        "node list -c",
        "node info /talker",
        "node info /listener",
        "node info /param_node",
        "node info /fibonacci_server",
        "node info /fibonacci_client",
        "node info /add_two_ints_client",
        "node info /py_managed",
        "node info /robot/imu_node --include-hidden",
        "node info /nobody",
        "topic list",
        "topic list -t",
        "topic list -v",
        "topic list -c",
        "topic list --include-hidden-topics",
        "topic info /chatter",
        "topic info /chatter -v",
        "topic info /latched --verbose",
        "topic info /best_effort -v",
        "topic info /nothing",
        "topic type /robot/imu",
        "topic type /nothing",
        "topic find std_msgs/msg/String",
        "topic find nope/msg/Nope",
        "service list",
        "service list -t",
        "service list -c",
        "service list --include-hidden-services",
        "service type /add_two_ints",
        "service type /nothing",
        "service find example_interfaces/srv/AddTwoInts",
        "service find nope/srv/Nope",
        "service info /add_two_ints",
        "service info /nothing",
        "action list",
        "action list -t",
        "action list -c",
        "action info /fibonacci",
        "action info /fibonacci -t",
        "action info /fibonacci -c",
        "action info /nothing",
        "action type /fibonacci",
        "action type /nothing",
        "lifecycle nodes",
        "lifecycle nodes -c",
        "lifecycle nodes -a",
    ]
    .into_iter()
    .map(case)
    .collect();
    // Without the daemons: each tool discovers the graph itself (ros2cli for its --spin-time,
    // 5 s for a Fast DDS graph to be complete on a loaded machine; horus-ros until the graph is
    // complete). Alone: their hidden nodes are on the graph, and ros2cli's discovery is not
    // niced.
    for line in [
        "node list --no-daemon --spin-time 5",
        "topic list -t --no-daemon --spin-time 5",
    ] {
        cases.push(case(line).alone());
    }
    cases
}

/// `interface`: the installed packages' files (both tools read the same `AMENT_PREFIX_PATH`).
fn interfaces() -> Vec<Case> {
    let mut cases: Vec<Case> = [
        "interface list",
        "interface list -m",
        "interface list -s",
        "interface list -a",
        "interface packages",
        "interface package nope",
        "interface show std_msgs/msg/Header",
        "interface show sensor_msgs/msg/Imu --all-comments",
        "interface show sensor_msgs/msg/Imu --no-comments",
        "interface show example_interfaces/srv/AddTwoInts",
        "interface show example_interfaces/action/Fibonacci",
        "interface show test_msgs/msg/Strings",
        "interface show std_msgs/msg/Nope",
        "interface proto sensor_msgs/msg/Imu",
        "interface proto std_msgs/msg/String --no-quotes",
        "interface proto test_msgs/msg/Strings",
    ]
    .into_iter()
    .map(case)
    .collect();
    // Python set order: Norm::SetOrder.
    for line in [
        "interface package std_msgs",
        "interface package example_interfaces",
    ] {
        cases.push(case(line).norm(&[Norm::SetOrder]));
    }
    cases.push(case("interface show -").stdin("std_msgs/msg/String\n"));
    cases.push(case("interface proto std_msgs/msg/Nope").known(Known::Ros2Traceback));
    cases
}

/// `topic echo|hz|bw|delay|pub`.
fn topics() -> Vec<Case> {
    // Norm::LostMessages: a subscription that matches mid-stream.
    let mut cases: Vec<Case> = [
        "topic echo /chatter --once",
        "topic echo /chatter --once --csv",
        "topic echo /chatter std_msgs/msg/String --once",
        "topic echo /chatter --once --field data",
        "topic echo /chatter --once --raw",
        "topic echo /chatter --once --filter 'm.data == \"Hello World\" and len(m.data) > 3'",
        "topic echo /chatter --filter 'm.data != \"Hello World\"' --timeout 1",
        "topic echo /chatter --once --qos-reliability best_effort --qos-durability volatile \
         --qos-history keep_last --qos-depth 1",
        "topic echo /long --once",
        "topic echo /long --once --full-length",
        "topic echo /long --once --truncate-length 5",
        "topic echo /robot/imu --once",
        "topic echo /robot/imu --once --csv",
        "topic echo /robot/imu --once --no-arr",
        "topic echo /robot/imu --once --csv --no-arr",
        "topic echo /robot/imu --once --truncate-length 2",
        "topic echo /robot/imu --once --flow-style",
        "topic echo /robot/imu --once --field orientation",
        "topic echo /robot/imu --once --field orientation_covariance",
        "topic echo /robot/imu --once --field orientation.v",
        "topic echo /strings --once",
        "topic echo /arrays --once",
        "topic echo /arrays --once --csv",
        "topic echo /arrays --once --field float32_values",
        "topic echo /arrays --once --field float64_values",
        "topic echo /arrays --once --field int8_values",
        "topic echo /arrays --once --field uint64_values",
        "topic echo /latched --once",
        // --qos-* alone: the other policies are sensor_data's, a best-effort reader, which gets
        // no history.
        "topic echo /latched --once --qos-reliability reliable --qos-durability transient_local",
        "topic echo /latched --once --qos-durability volatile --timeout 1",
        "topic echo /best_effort --once",
        "topic echo /nothing",
        "topic echo /chatter std_msgs/msg/Nope --once",
    ]
    .into_iter()
    .map(|line| case(line).norm(&[Norm::LostMessages]))
    .collect();
    // A type no file describes for horus-ros: taken from the publisher's node
    // (`~/get_type_description`); ros2cli reads its files. Norm::LostMessages.
    for line in [
        "topic echo /strings --once",
        "topic echo /strings --once --csv",
    ] {
        cases.push(
            case(line)
                .norm(&[Norm::LostMessages])
                .horus_without("AMENT_PREFIX_PATH"),
        );
    }
    // Norm::LostMessages, Norm::MessageInfo.
    cases
        .push(case("topic echo /chatter --once -i").norm(&[Norm::LostMessages, Norm::MessageInfo]));
    // A reliable reader of a best-effort publisher: rcl's warning of the incompatible QoS, a log
    // line (Norm::LogLine), and no message; 3 s for ros2cli's node to match the publisher.
    cases.push(
        case("topic echo /best_effort --once --qos-reliability reliable --timeout 3")
            .norm(&[Norm::LogLine]),
    );
    // Measured: Norm::Numbers (the first reports only); Norm::NotYetPublished.
    for (line, lines) in [
        ("topic hz /chatter --window 5", 2),
        ("topic bw /chatter", 3),
        ("topic delay /robot/imu", 2),
    ] {
        cases.push(
            case(line)
                .stream(lines)
                .norm(&[Norm::NotYetPublished, Norm::Numbers]),
        );
    }
    // Norm::WaitingForSubscriptions: `-w` waits for the peer's subscription.
    for line in [
        "topic pub --once /pub_target std_msgs/msg/String '{data: hi}'",
        "topic pub -t 3 -r 20 /pub_target std_msgs/msg/String '{data: three}'",
        "topic pub -t 4 -r 20 -p 2 /pub_target std_msgs/msg/String",
        "topic pub --once -w 0 /pub_target std_msgs/msg/String",
        "topic pub --once --qos-durability transient_local /pub_target std_msgs/msg/String \
         '{data: kept}'",
        "topic pub --once /pub_target std_msgs/msg/String '{dat: hi}'",
    ] {
        cases.push(case(line).norm(&[Norm::WaitingForSubscriptions]));
    }
    cases.push(case("topic pub --once /pub_target std_msgs/msg/Nope '{}'"));
    cases.push(
        case("topic pub --once /pub_target std_msgs/msg/String '{data: [1]}'")
            .norm(&[Norm::WaitingForSubscriptions]),
    );
    cases.push(
        case("topic pub --once /pub_target std_msgs/msg/String '{data: [1'")
            .known(Known::Ros2Traceback),
    );
    cases
}

/// `service call`. Norm::WaitingForService.
fn services() -> Vec<Case> {
    let mut cases: Vec<Case> = [
        "service call /add_two_ints example_interfaces/srv/AddTwoInts '{a: 2, b: 3}'",
        "service call /add_two_ints example_interfaces/srv/AddTwoInts",
        "service call /add_two_ints example_interfaces/AddTwoInts 'a: -1'",
        "service call /add_two_ints example_interfaces/srv/AddTwoInts '{a: 2, c: 3}'",
        "service call /param_node/get_parameters rcl_interfaces/srv/GetParameters \
         '{names: [count, name]}'",
    ]
    .into_iter()
    .map(|line| case(line).norm(&[Norm::WaitingForService]))
    .collect();
    cases.push(
        case("service call /add_two_ints example_interfaces/srv/AddTwoInts --stdin")
            .stdin("{a: 40, b: 2}\n")
            .norm(&[Norm::WaitingForService]),
    );
    cases.push(case(
        "service call /add_two_ints example_interfaces/srv/Nope '{}'",
    ));
    cases.push(
        case("service call /add_two_ints example_interfaces/srv/AddTwoInts '{a: 2'")
            .known(Known::Ros2Traceback),
    );
    cases
}

/// `param`: every verb, every parameter type, YAML typing of values, files, compared as printed.
/// Cases of one verb may run at once:
/// what each prints does not depend on the others (setting a value twice answers the same
/// twice); the next verb sees the state they left.
fn params(f: &Files) -> Vec<Case> {
    let lines = [
        "param list".to_owned(),
        "param list /param_node".to_owned(),
        "param list param_node --param-type".to_owned(),
        "param list /param_node --filter '.*s$' --param-type".to_owned(),
        "param list /param_node --param-prefixes nested ratio".to_owned(),
        "param list /nobody".to_owned(),
        "param describe /param_node count ratio fixed name dynamic nested.depth".to_owned(),
        "param describe /param_node count nope".to_owned(),
        "param dump /param_node".to_owned(),
        "param dump /nobody".to_owned(),
    ]
    .into_iter()
    .chain(
        [
            "flag", "ratio", "name", "numbers", "doubles", "words", "nope",
        ]
        .map(|name| format!("param get /param_node {name}")),
    )
    .chain([
        "param get /param_node words --hide-type".to_owned(),
        "param get /nobody x".to_owned(),
    ])
    .chain(
        [
            "count 10",
            "count x",
            "ratio 2.0",
            "name 'new value'",
            "name \\'5\\'",
            "numbers '[4, 0x10]'",
            "doubles '[0.5, 1.0e+3]'",
            "words '[x, '\\''y'\\'', \"z w\"]'",
            "fixed 8",
            "nope 1",
            "dynamic yes",
        ]
        .map(|set| format!("param set /param_node {set}")),
    )
    .chain([
        "param set /nobody x 1".to_owned(),
        "param dump /param_node".to_owned(),
    ])
    .chain(
        [
            f.wildcard.clone(),
            format!("{} --no-use-wildcard", f.wildcard),
            f.only_wildcard.clone(),
            format!("{} --no-use-wildcard", f.only_wildcard),
            f.dump.clone(),
            f.other_node.clone(),
        ]
        .map(|file| format!("param load /param_node {file}")),
    )
    .chain([
        "param dump /param_node".to_owned(),
        "param delete /param_node nope".to_owned(),
        "param delete /param_node fixed".to_owned(),
    ]);
    let mut cases: Vec<Case> = lines.map(|line| case(&line)).collect();
    for file in [&f.bad_yaml, &f.missing] {
        cases.push(case(&format!("param load /param_node {file}")).known(Known::Ros2Traceback));
    }
    // Deleting changes the node: the parameter is declared again after each run.
    cases.push(
        case("param delete /param_node dynamic").around(&[], &[r#"{"redeclare": "dynamic"}"#]),
    );
    cases
}

/// `action send_goal`: Norm::GoalId.
fn actions() -> Vec<Case> {
    let norms = [Norm::GoalId];
    let mut cases: Vec<Case> = [
        "action send_goal /fibonacci example_interfaces/action/Fibonacci '{order: 4}'",
        "action send_goal /fibonacci example_interfaces/action/Fibonacci '{order: 4}' -f",
        "action send_goal --feedback /fibonacci example_interfaces/Fibonacci 'order: 2'",
        "action send_goal /fibonacci example_interfaces/action/Fibonacci '{order: -1}' -f",
        "action send_goal /fibonacci example_interfaces/action/Fibonacci '{ordr: 4}'",
    ]
    .into_iter()
    .map(|line| case(line).norm(&norms))
    .collect();
    cases.push(
        case("action send_goal /fibonacci example_interfaces/action/Fibonacci --stdin -f")
            .stdin("order: 3\n")
            .norm(&norms),
    );
    cases.push(case(
        "action send_goal /fibonacci example_interfaces/action/Nope '{}'",
    ));
    cases
}

/// `lifecycle get|list|set`, through every state the transitions reach; the peer moves the node
/// back after each run. Compared as printed.
fn lifecycles() -> Vec<Case> {
    let z = [];
    let mut cases: Vec<Case> = [
        "lifecycle get /py_managed",
        "lifecycle get",
        "lifecycle get /nobody",
        "lifecycle list py_managed",
        "lifecycle list /py_managed -a",
        "lifecycle set /py_managed activate",
        "lifecycle set /py_managed nope",
    ]
    .into_iter()
    .map(|line| case(line).norm(&z))
    .collect();
    let (configure, cleanup) = (lifecycle("configure"), lifecycle("cleanup"));
    let (activate, deactivate) = (lifecycle("activate"), lifecycle("deactivate"));
    let active = [configure.as_str(), activate.as_str()];
    let back = [deactivate.as_str(), cleanup.as_str()];
    for line in [
        "lifecycle set /py_managed configure",
        "lifecycle set /py_managed 1",
    ] {
        cases.push(case(line).norm(&z).around(&[], &[&cleanup]));
    }
    for line in ["lifecycle get", "lifecycle list /py_managed"] {
        cases.push(case(line).norm(&z).around(&active, &back));
    }
    cases.push(
        case("lifecycle set /py_managed deactivate")
            .norm(&z)
            .around(&active, &[&cleanup]),
    );
    // A callback that fails: "Transitioning failed", exit status 0; the node stays where it was.
    cases.push(case("lifecycle set /py_managed configure").norm(&z).around(
        &[r#"{"behave": {"on_configure": "failure"}}"#],
        &[r#"{"behave": {"on_configure": "success"}}"#],
    ));
    cases
}
