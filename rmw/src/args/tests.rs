//! rcl 9.2 `test/rcl/test_arguments.cpp`, ported case by case, and the remapping rules of
//! `test/rcl/test_remap.cpp` that `--ros-args` feeds.

use super::*;

fn argv(ros: &[&str]) -> Vec<String> {
    std::iter::once("process_name")
        .chain(ros.iter().copied())
        .map(str::to_owned)
        .collect()
}

/// rcl's `are_known_ros_args`: parsed, and no unknown ROS argument.
fn known(args: &[&str]) -> bool {
    Arguments::parse(&argv(args)).is_ok_and(|a| a.unparsed_ros_args.is_empty())
}

/// rcl's `are_valid_ros_args`: parsed.
fn valid(args: &[&str]) -> bool {
    Arguments::parse(&argv(args)).is_ok()
}

/// A parameters file for `--params-file` (`test_params.yaml` beside this file).
fn params_file() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/src/args/test_params.yaml").to_owned()
}

#[test]
fn check_known_vs_unknown_args() {
    for ok in [
        &["--ros-args", "-r", "__node:=node_name"][..],
        &["--ros-args", "-r", "old_name:__node:=node_name"],
        &["--ros-args", "-r", "old_name:__node:=nodename123"],
        &["--ros-args", "-r", "__node:=nodename123"],
        &["--ros-args", "-r", "__ns:=/foo/bar"],
        &["--ros-args", "-r", "__ns:=/"],
        &["--ros-args", "-r", "_:=kq"],
        &["--ros-args", "-r", "nodename:__ns:=/foobar"],
        &["--ros-args", "-r", "foo:=bar"],
        &["--ros-args", "-r", "~/foo:=~/bar"],
        &["--ros-args", "-r", "/foo/bar:=bar"],
        &["--ros-args", "-r", "foo:=/bar"],
        &["--ros-args", "-r", "/foo123:=/bar123"],
        &["--ros-args", "-r", "node:/foo123:=/bar123"],
        &["--ros-args", "-r", "rostopic:=/foo/bar"],
        &["--ros-args", "-r", "rosservice:=baz"],
        &["--ros-args", "-r", "rostopic://rostopic:=rosservice"],
        &["--ros-args", "-r", "rostopic:///rosservice:=rostopic"],
        &["--ros-args", "-r", "rostopic:///foo/bar:=baz"],
        &["--ros-args", "-p", "foo:=bar"],
        &[
            "--ros-args",
            "-p",
            "qos_overrides./foo/bar.publisher.history:=keep_last",
        ],
        &["--ros-args", "-p", "foo.bar:=bar"],
        &["--ros-args", "-p", "node:foo:=bar"],
        &["--ros-args", "-p", "fizz123:=buzz456"],
        &["--ros-args", "--log-config-file", "file.config"],
        &["--ros-args", "--log-level", "UNSET"],
        &["--ros-args", "--log-level", "DEBUG"],
        &["--ros-args", "--log-level", "INFO"],
        &["--ros-args", "--log-level", "WARN"],
        &["--ros-args", "--log-level", "ERROR"],
        &["--ros-args", "--log-level", "FATAL"],
        &["--ros-args", "--log-level", "debug"],
        &["--ros-args", "--log-level", "Info"],
        &["--ros-args", "--log-file-name", "filename"],
        &["--ros-args", "--enable-rosout-logs"],
        &["--ros-args", "--disable-rosout-logs"],
        &["--ros-args", "--enable-stdout-logs"],
        &["--ros-args", "--disable-stdout-logs"],
        &["--ros-args", "--enable-external-lib-logs"],
        &["--ros-args", "--disable-external-lib-logs"],
    ] {
        assert!(known(ok), "{ok:?}");
    }
    let file = params_file();
    assert!(known(&["--ros-args", "--params-file", &file]));
    for unknown in [
        &["--ros-args", "--custom-ros-arg"][..],
        &["--ros-args", "__node:=node_name"],
        &["--ros-args", "old_name:__node:=node_name"],
        &["--ros-args", "/foo/bar:=bar"],
        &["--ros-args", "foo:=/bar"],
        &["--ros-args", "file_name.yaml"],
        &["--ros-args", "--log", "foo"],
        &["--ros-args", "--loglevel", "foo"],
        &["--ros-args", "--logfile-name", "filename"],
        &["--ros-args", "--log-filename", "filename"],
        &["--ros-args", "stdout-logs"],
        &["--ros-args", "external-lib-logs"],
    ] {
        assert!(!known(unknown), "{unknown:?}");
    }
}

#[test]
fn check_valid_vs_invalid_args() {
    let file = params_file();
    assert!(valid(&[
        "--ros-args",
        "-p",
        "foo:=bar",
        "-r",
        "__node:=node_name",
        "--params-file",
        &file,
        "--log-level",
        "INFO",
        "--log-config-file",
        "file.config",
        "--log-file-name",
        "filename"
    ]));
    assert!(valid(&["--ros-args", "--custom-ros-arg"]));
    for invalid in [
        &["--ros-args", "-r"][..],
        &["--ros-args", "--remap"],
        &["--ros-args", "-r", ":"],
        &["--ros-args", "-r", "1"],
        &["--ros-args", "-r", "~"],
        &["--ros-args", "-r", ":="],
        &["--ros-args", "-r", "foo:="],
        &["--ros-args", "-r", ":=bar"],
        &["--ros-args", "-r", "::="],
        &["--ros-args", "-r", "1:="],
        &["--ros-args", "-r", "~:="],
        &["--ros-args", "-r", "__node:="],
        &["--ros-args", "-r", "__node:=/foo/bar"],
        &["--ros-args", "-r", "__ns:="],
        &["--ros-args", "-r", "__ns:=foo"],
        &["--ros-args", "-r", ":__node:=nodename"],
        &["--ros-args", "-r", "~:__node:=nodename"],
        &["--ros-args", "-r", "}foo:=/bar"],
        &["--ros-args", "-r", "f oo:=/bar"],
        &["--ros-args", "-r", "foo:=/b ar"],
        &["--ros-args", "-r", "f{oo:=/bar"],
        &["--ros-args", "-r", "foo:=/b}ar"],
        &["--ros-args", "-r", "rostopic://:=rosservice"],
        &["--ros-args", "-r", "rostopic::=rosservice"],
        &["--ros-args", "-p"],
        &["--ros-args", "-p", ":="],
        &["--ros-args", "-p", "foo:="],
        &["--ros-args", "-p", ":=bar"],
        &["--ros-args", "-p", ":"],
        &["--ros-args", "-p", "1"],
        &["--ros-args", "-p", "~"],
        &["--ros-args", "-p", "::="],
        &["--ros-args", "-p", "1:="],
        &["--ros-args", "-p", "~:="],
        &["--ros-args", "-p", "__node:="],
        &["--ros-args", "-p", "__node:=/foo/bar"],
        &["--ros-args", "-p", "__ns:=foo"],
        &["--ros-args", "-p", ":__node:=nodename"],
        &["--ros-args", "-p", "~:__node:=nodename"],
        &["--ros-args", "-p", "}foo:=/bar"],
        &["--ros-args", "--param", "}foo:=/bar"],
        &["--ros-args", "-p", "f oo:=/bar"],
        &["--ros-args", "--param", "f oo:=/bar"],
        &["--ros-args", "-e"],
        &["--ros-args", "--enclave"],
        &["--ros-args", "--params-file"],
        &["--ros-args", "--log-config-file"],
        &["--ros-args", "--log-level"],
        &["--ros-args", "--log-file-name"],
    ] {
        assert!(!valid(invalid), "{invalid:?}");
    }
}

#[test]
fn rcl_error_messages() {
    let err = |a: &[&str]| match Arguments::parse(&argv(a)) {
        Err(ArgumentsError::Invalid(m)) => m,
        other => panic!("{a:?}: {other:?}"),
    };
    assert_eq!(
        err(&["--ros-args", "-r"]),
        "Couldn't parse trailing -r flag. No remap rule found."
    );
    assert_eq!(
        err(&["--ros-args", "--param"]),
        "Couldn't parse trailing --param flag. No parameter override rule found."
    );
    assert_eq!(
        err(&["--ros-args", "--params-file"]),
        "Couldn't parse trailing --params-file flag. No file path provided."
    );
    assert_eq!(
        err(&["--ros-args", "--log-level"]),
        "Couldn't parse trailing log level flag: '--log-level'. No log level provided."
    );
    assert_eq!(
        err(&["--ros-args", "-e"]),
        "Couldn't parse trailing -e flag. No enclave path provided."
    );
    assert_eq!(
        err(&["--ros-args", "-r", "foo:="]),
        "Couldn't parse remap rule: '-r foo:='. Error: Expected lexeme type 18, got 1 at index 5"
    );
    assert_eq!(
        err(&["--ros-args", "-r", "*:=bar"]),
        "Couldn't parse remap rule: '-r *:=bar'. Error: Wildcard '*' is not implemented"
    );
    assert_eq!(
        err(&["--ros-args", "-r", "foo:=\\1"]),
        "Couldn't parse remap rule: '-r foo:=\\1'. Error: Backreferences are not implemented"
    );
    assert_eq!(
        err(&["--ros-args", "--log-level", "loud"]),
        "Couldn't parse log level: '--log-level loud'. Error: Argument does not use a valid severity level"
    );
    assert_eq!(
        Arguments::parse_strict(&argv(&["--ros-args", "--custom-ros-arg", "--foo"])),
        Err(ArgumentsError::Unknown(vec![
            "--custom-ros-arg".into(),
            "--foo".into()
        ]))
    );
    assert_eq!(
        ArgumentsError::Unknown(vec!["--a".into(), "b".into()]).to_string(),
        "found unknown ROS arguments: '--a', 'b'"
    );
}

fn unparsed(a: &[&str]) -> (Vec<usize>, Vec<usize>) {
    let p = Arguments::parse(&argv(a)).expect("parses");
    (p.unparsed_args, p.unparsed_ros_args)
}

#[test]
fn unparsed_args_as_rcl_counts_them() {
    assert_eq!(unparsed(&[]), (vec![0], vec![]));
    assert_eq!(unparsed(&["--ros-args"]), (vec![0], vec![]));
    assert_eq!(unparsed(&["--ros-args", "--"]), (vec![0], vec![]));
    assert_eq!(
        unparsed(&[
            "--ros-args",
            "-r",
            "/foo/bar:=/fiz/buz",
            "--remap",
            "foo:=/baz"
        ]),
        (vec![0], vec![])
    );
    assert_eq!(
        unparsed(&["--ros-args", "--ros-args", "-r", "/foo/bar:=/fiz/buz"]),
        (vec![0], vec![])
    );
    assert_eq!(
        unparsed(&["--ros-args", "-r", "/foo/bar:=/fiz/buz", "--"]),
        (vec![0], vec![])
    );
    assert_eq!(
        unparsed(&["--ros-args", "-r", "/foo/bar:=/fiz/buz", "--", "--"]),
        (vec![0, 5], vec![])
    );
    assert_eq!(
        unparsed(&[
            "--ros-args",
            "/foo/bar:=",
            "-r",
            "bar:=/fiz/buz",
            "}bar:=fiz",
            "--",
            "arg"
        ]),
        (vec![0, 7], vec![2, 5])
    );
    assert_eq!(
        unparsed(&["--ros-args", "--", "arg", "--ros-args"]),
        (vec![0, 3], vec![])
    );
    let p = Arguments::parse(&argv(&["--foo", "--ros-args", "-r", "a:=b", "--", "--bar"]))
        .expect("parses");
    assert_eq!(p.non_ros_args(), ["process_name", "--foo", "--bar"]);
}

#[test]
fn two_namespaces_first_wins() {
    let p = Arguments::parse(&argv(&[
        "--ros-args",
        "-r",
        "__ns:=/foo/bar",
        "-r",
        "__ns:=/fiz/buz",
    ]))
    .expect("parses");
    assert_eq!(p.remap_namespace("any"), Some("/foo/bar"));
}

#[test]
fn deprecated_remap_outside_ros_args() {
    let p = Arguments::parse(&argv(&["__node:=renamed", "plain"])).expect("parses");
    assert_eq!(p.remap_node_name("n"), Some("renamed"));
    assert_eq!(p.unparsed_args, [0, 2]);
}

#[test]
fn node_name_and_namespace_rules() {
    let p = Arguments::parse(&argv(&[
        "--ros-args",
        "-r",
        "talker:__node:=speaker",
        "-r",
        "__ns:=/robot1",
        "-r",
        "__name:=everyone",
    ]))
    .expect("parses");
    assert_eq!(p.remap_node_name("talker"), Some("speaker"));
    assert_eq!(p.remap_node_name("listener"), Some("everyone"));
    assert_eq!(p.remap_namespace("talker"), Some("/robot1"));
}

#[test]
fn topic_and_service_rules() {
    let node = NodeName::new("talker").expect("name");
    let ns = Namespace::new("/robot1").expect("ns");
    let p = Arguments::parse(&argv(&[
        "--ros-args",
        "-r",
        "listener:chatter:=/ignored",
        "-r",
        "chatter:=babble",
        "-r",
        "rostopic://only_topic:=/t",
        "-r",
        "rosservice://only_service:=/s",
        "-r",
        "~/private:=/public",
        "-r",
        "/abs:=rel",
    ]))
    .expect("parses");
    assert_eq!(
        p.remap_topic("/robot1/chatter", &node, &ns).as_deref(),
        Some("/robot1/babble")
    );
    assert_eq!(
        p.remap_service("/robot1/chatter", &node, &ns).as_deref(),
        Some("/robot1/babble")
    );
    assert_eq!(
        p.remap_topic("/robot1/only_topic", &node, &ns).as_deref(),
        Some("/t")
    );
    assert_eq!(p.remap_service("/robot1/only_topic", &node, &ns), None);
    assert_eq!(
        p.remap_service("/robot1/only_service", &node, &ns)
            .as_deref(),
        Some("/s")
    );
    assert_eq!(p.remap_topic("/robot1/only_service", &node, &ns), None);
    assert_eq!(
        p.remap_topic("/robot1/talker/private", &node, &ns)
            .as_deref(),
        Some("/public")
    );
    assert_eq!(
        p.remap_topic("/abs", &node, &ns).as_deref(),
        Some("/robot1/rel")
    );
    assert_eq!(p.remap_topic("/robot1/other", &node, &ns), None);
    let listener = NodeName::new("listener").expect("name");
    assert_eq!(
        p.remap_topic("/robot1/chatter", &listener, &ns).as_deref(),
        Some("/ignored"),
        "a node-specific rule first"
    );
}

fn int(v: &ParameterValue) -> Option<i64> {
    (v.r#type == ParameterType::PARAMETER_INTEGER).then_some(v.integer_value)
}

#[test]
fn parameter_values_are_typed_as_rcl_yaml_param_parser_types_them() {
    let one = |s: &str| parse_param_rule(&format!("x:={s}")).expect(s).value;
    assert_eq!(int(&one("1")), Some(1));
    assert_eq!(one("-3").integer_value, -3);
    assert_eq!(one("1.5").r#type, ParameterType::PARAMETER_DOUBLE);
    assert_eq!(one("1.5").double_value, 1.5);
    assert_eq!(one("true").r#type, ParameterType::PARAMETER_BOOL);
    assert!(one("yes").bool_value);
    assert!(!one("Off").bool_value);
    assert_eq!(one("'1'").r#type, ParameterType::PARAMETER_STRING);
    assert_eq!(one("'1'").string_value, "1");
    assert_eq!(one("hello").string_value, "hello");
    assert_eq!(one("/dev/ttyUSB0").string_value, "/dev/ttyUSB0");
    assert_eq!(one("[1, 2]").integer_array_value, [1, 2]);
    assert_eq!(one("[a, 'b']").string_array_value, ["a", "b"]);
    assert_eq!(one("[true, false]").bool_array_value, [true, false]);
    assert!(parse_param_rule("x:=[1, a]").is_err(), "mixed sequence");
    let r = parse_param_rule("lidar:port:=5").expect("rule");
    assert_eq!((r.node.as_str(), r.name.as_str()), ("/lidar", "port"));
    assert_eq!(parse_param_rule("a.b:=1").expect("rule").name, "a.b");
}

#[test]
fn params_files_and_node_patterns() {
    let file = params_file();
    let p = Arguments::parse(&argv(&[
        "--ros-args",
        "--params-file",
        &file,
        "-p",
        "foo:=2",
    ]))
    .expect("parses");
    let names = |fqn: &str| {
        p.parameters_for(fqn)
            .into_iter()
            .map(|(n, _)| n)
            .collect::<Vec<_>>()
    };
    assert_eq!(names("/lidar"), ["foo", "nested.bar", "port", "on", "foo"]);
    assert_eq!(names("/robot/arm"), ["foo", "nested.bar", "joints", "foo"]);
    assert_eq!(names("/other"), ["foo", "nested.bar", "foo"]);
    let lidar = p.parameters_for("/lidar");
    assert_eq!(lidar[2].1.string_value, "/dev/ttyUSB0");
    assert_eq!(int(&lidar[4].1), Some(2), "-p after the file wins");
    assert_eq!(p.parameter_files, std::slice::from_ref(&file));
    assert!(node_pattern_matches("/**", "/a/b"));
    assert!(node_pattern_matches("/a/*", "/a/b"));
    assert!(!node_pattern_matches("/a/*", "/a/b/c"));
    assert!(node_pattern_matches("/**/c", "/a/b/c"));
    let bad = Arguments::parse(&argv(&["--ros-args", "--params-file", "/nonexistent.yaml"]));
    assert!(matches!(bad, Err(ArgumentsError::Invalid(m))
        if m.starts_with("Couldn't parse params file: '--params-file /nonexistent.yaml'. Error: ")));
}

#[test]
fn log_levels_and_flags() {
    let p = Arguments::parse(&argv(&[
        "--ros-args",
        "--log-level",
        "debug",
        "--log-level",
        "talker:=error",
        "--disable-rosout-logs",
        "-e",
        "/secure",
    ]))
    .expect("parses");
    assert_eq!(p.log_level_for("talker"), Some(LogSeverity::Error));
    assert_eq!(p.log_level_for("other"), Some(LogSeverity::Debug));
    assert_eq!(p.log_rosout_disabled, Some(true));
    assert_eq!(p.enclave.as_deref(), Some("/secure"));
    assert!(Arguments::parse(&argv(&["--ros-args", "--log-level", ":=debug"])).is_err());
}
