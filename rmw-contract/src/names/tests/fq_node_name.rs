use crate::names::{
    FqNodeNameError, FullyQualifiedNodeName, Namespace, NamespaceError, NodeName, NodeNameError,
};

// Joining as rcl (jazzy) src/rcl/node.c builds fq_name; parsing as ros2cli
// `ros2 node info /ns/name` expects.
#[test]
fn fully_qualified_node_names() {
    let cases = [
        ("/talker", "/", "talker"),
        ("/ns/talker", "/ns", "talker"),
        ("/a/b/c", "/a/b", "c"),
    ];
    for (full, ns, name) in cases {
        let fq = FullyQualifiedNodeName::new(full).expect("valid");
        assert_eq!(fq.namespace().as_str(), ns);
        assert_eq!(fq.name().as_str(), name);
        assert_eq!(fq.to_string(), full);
        let joined = FullyQualifiedNodeName::from_parts(
            &Namespace::new(ns).expect("valid"),
            &NodeName::new(name).expect("valid"),
        );
        assert_eq!(joined, fq);
    }
    let errors = [
        ("talker", FqNodeNameError::NotAbsolute),
        ("/", FqNodeNameError::NodeName(NodeNameError::Empty)),
        ("/ns/", FqNodeNameError::NodeName(NodeNameError::Empty)),
        (
            "/ns/9x",
            FqNodeNameError::NodeName(NodeNameError::StartsWithNumber),
        ),
        (
            "//talker",
            FqNodeNameError::Namespace(NamespaceError::RepeatedForwardSlash { index: 1 }),
        ),
        ("/ns/x/", FqNodeNameError::NodeName(NodeNameError::Empty)),
        (
            "/n s/x",
            FqNodeNameError::Namespace(NamespaceError::InvalidCharacter { index: 2 }),
        ),
    ];
    for (input, expected) in errors {
        assert_eq!(FullyQualifiedNodeName::new(input), Err(expected), "{input}");
    }
}
