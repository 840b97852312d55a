use crate::names::{
    expand_name, ExpandError, Namespace, NodeName, ServiceName, TopicName, TopicNameError,
    UnexpandedNameError,
};

fn node_and_ns(node: &str, ns: &str) -> (NodeName, Namespace) {
    (
        NodeName::new(node).expect("test node name"),
        Namespace::new(ns).expect("test namespace"),
    )
}

// Cases from ros2/rcl (jazzy, 9.2) rcl/test/rcl/test_expand_topic_name.cpp
// (`normal`, `various_valid_topics`): input, node, namespace, expected.
#[test]
fn rcl_various_valid_topics() {
    let cases = [
        (
            "{node}/chatter",
            "my_node",
            "/my_ns",
            "/my_ns/my_node/chatter",
        ),
        ("/chatter", "my_node", "/my_ns", "/chatter"),
        ("chatter", "my_node", "/my_ns", "/my_ns/chatter"),
        (
            "{node}/chatter",
            "my_node",
            "/my_ns",
            "/my_ns/my_node/chatter",
        ),
        ("/{node}", "my_node", "/my_ns", "/my_node"),
        ("{node}", "my_node", "/my_ns", "/my_ns/my_node"),
        ("{ns}", "my_node", "/my_ns", "/my_ns"),
        ("{namespace}", "my_node", "/my_ns", "/my_ns"),
        (
            "{namespace}/{node}/chatter",
            "my_node",
            "/my_ns",
            "/my_ns/my_node/chatter",
        ),
        ("ping", "my_node", "/", "/ping"),
        ("ping", "my_node", "/my_ns", "/my_ns/ping"),
        ("/ping", "my_node", "/", "/ping"),
        ("/ping", "my_node", "/my_ns", "/ping"),
        ("~", "my_node", "/", "/my_node"),
        ("~", "my_node", "/my_ns", "/my_ns/my_node"),
        ("~/ping", "my_node", "/", "/my_node/ping"),
        ("~/ping", "my_node", "/my_ns", "/my_ns/my_node/ping"),
    ];
    for (input, node, ns, expected) in cases {
        let (node, ns) = node_and_ns(node, ns);
        assert_eq!(
            expand_name(input, &node, &ns, &[]).as_deref(),
            Ok(expected),
            "input {input:?}"
        );
        let topic = TopicName::expand(input, &node, &ns).expect("valid expansion");
        assert_eq!(topic.as_str(), expected);
        let service = ServiceName::expand(input, &node, &ns).expect("valid expansion");
        assert_eq!(service.as_str(), expected);
    }
}

// From the same table: rcl expands "/foo/{namespace}" to "/foo//my_ns" and
// leaves the '//' to rmw_validate_full_topic_name (rcl node_resolve_name.c).
#[test]
fn rcl_expansion_caught_by_rmw_validation() {
    let (node, ns) = node_and_ns("my_node", "/my_ns");
    assert_eq!(
        expand_name("/foo/{namespace}", &node, &ns, &[]).as_deref(),
        Ok("/foo//my_ns")
    );
    assert_eq!(
        TopicName::expand("/foo/{namespace}", &node, &ns),
        Err(ExpandError::InvalidExpansion {
            expanded: "/foo//my_ns".to_owned(),
            cause: TopicNameError::RepeatedForwardSlash { index: 5 },
        })
    );
}

// `invalid_arguments`, `unknown_substitution` and `custom_substitution` of
// rcl/test/rcl/test_expand_topic_name.cpp (invalid node names and namespaces
// cannot reach our API: NodeName/Namespace are validated on construction).
#[test]
fn rcl_invalid_input_and_substitutions() {
    let (node, ns) = node_and_ns("my_node", "/my_ns");
    assert_eq!(
        TopicName::expand("white space", &node, &ns),
        Err(ExpandError::InvalidInput(
            UnexpandedNameError::InvalidCharacter { index: 5 }
        ))
    );
    let unknown = TopicName::expand("{doesnotexist}", &node, &ns);
    assert_eq!(
        unknown,
        Err(ExpandError::UnknownSubstitution {
            substitution: "{doesnotexist}".to_owned()
        })
    );
    assert_eq!(
        unknown.map(|_| ()).err().map(|e| e.to_string()).as_deref(),
        Some("unknown substitution: {doesnotexist}")
    );
    let (node, ns) = node_and_ns("bar", "/foo");
    assert!(matches!(
        ServiceName::expand("{unknown}/test", &node, &ns),
        Err(ExpandError::UnknownSubstitution { .. })
    ));
    let (node, ns) = node_and_ns("my_node", "/my_ns");
    let custom = TopicName::expand_with("{ping}", &node, &ns, &[("ping", "pong")]);
    assert_eq!(custom.as_ref().map(TopicName::as_str), Ok("/my_ns/pong"));
}

#[test]
fn expansion_edge_cases() {
    let (node, root) = node_and_ns("n", "/");
    // "{ns}" in the root namespace gives "/" (and "{ns}/x" gives "//x"), as in rcl
    assert_eq!(expand_name("{ns}", &node, &root, &[]).as_deref(), Ok("/"));
    assert_eq!(
        expand_name("{ns}/x", &node, &root, &[]).as_deref(),
        Ok("//x")
    );
    assert!(matches!(
        TopicName::expand("{ns}/x", &node, &root),
        Err(ExpandError::InvalidExpansion { .. })
    ));
    // "{}" passes rcl validation but is an unknown substitution
    assert_eq!(
        expand_name("{}", &node, &root, &[]),
        Err(ExpandError::UnknownSubstitution {
            substitution: "{}".to_owned()
        })
    );
    // a substitution value is inserted verbatim, once per occurrence
    assert_eq!(
        expand_name("{a}/{a}_{node}", &node, &root, &[("a", "x")]).as_deref(),
        Ok("/x/x_n")
    );
}
