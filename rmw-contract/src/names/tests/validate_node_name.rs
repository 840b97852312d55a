use crate::names::{NodeName, NodeNameError, NODE_NAME_MAX_LENGTH};

// Cases from ros2/rmw (jazzy) rmw/test/test_validate_node_name.cpp.
#[test]
fn rmw_test_validate_node_name() {
    use NodeNameError as E;
    let long_digits = "0".repeat(NODE_NAME_MAX_LENGTH + 1);
    let long_letters = "a".repeat(NODE_NAME_MAX_LENGTH + 1);
    let cases: &[(&str, Result<(), E>)] = &[
        ("nodename", Ok(())),
        ("node_name", Ok(())),
        ("", Err(E::Empty)),
        ("node/name", Err(E::InvalidCharacter { index: 4 })),
        ("node_{name}", Err(E::InvalidCharacter { index: 5 })),
        ("~node_name", Err(E::InvalidCharacter { index: 0 })),
        ("with spaces", Err(E::InvalidCharacter { index: 4 })),
        ("with.periods", Err(E::InvalidCharacter { index: 4 })),
        ("42node", Err(E::StartsWithNumber)),
        // length is not the first error reported
        (&long_digits, Err(E::StartsWithNumber)),
        (&long_letters, Err(E::TooLong { length: 256 })),
    ];
    for (input, expected) in cases {
        assert_eq!(&NodeName::new(input).map(|_| ()), expected, "{input:?}");
    }
    // rmw's invalid_index for the errors that carry no index
    assert_eq!(E::Empty.invalid_index(), 0);
    assert_eq!(E::StartsWithNumber.invalid_index(), 0);
    let too_long = E::TooLong { length: 256 };
    assert_eq!(too_long.invalid_index(), NODE_NAME_MAX_LENGTH - 1);
}

#[test]
fn node_name_traits_and_messages() {
    let name: NodeName = "talker".parse().expect("valid");
    assert_eq!(name.to_string(), "talker");
    assert_eq!(name, "talker");
    assert!(NodeName::try_from("_hidden").expect("valid").is_hidden());
    assert!(!name.is_hidden());
    // rmw_node_name_validation_result_string
    assert_eq!(
        NodeNameError::StartsWithNumber.to_string(),
        "node name must not start with a number"
    );
    assert_eq!(
        NodeNameError::TooLong { length: 300 }.to_string(),
        "node name length should not exceed '255' (length 300)"
    );
}
