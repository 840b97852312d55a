use crate::names::{Namespace, NamespaceError, NAMESPACE_MAX_LENGTH};

// Cases from ros2/rmw (jazzy) rmw/test/test_validate_namespace.cpp.
#[test]
fn rmw_test_validate_namespace() {
    use NamespaceError as E;
    let long = "a".repeat(NAMESPACE_MAX_LENGTH + 1);
    let long_absolute = format!("/{long}");
    let cases: &[(&str, Result<(), E>)] = &[
        ("/", Ok(())),
        ("/basename_only", Ok(())),
        ("/with_one/heirarchy", Ok(())),
        ("", Err(E::Empty)),
        ("not_absolute", Err(E::NotAbsolute)),
        ("not/absolute", Err(E::NotAbsolute)),
        ("/ends/with/", Err(E::EndsWithForwardSlash { index: 10 })),
        ("/~/unexpanded_tilde", Err(E::InvalidCharacter { index: 1 })),
        (
            "/unexpanded_sub/{node}",
            Err(E::InvalidCharacter { index: 16 }),
        ),
        ("/question?", Err(E::InvalidCharacter { index: 9 })),
        ("/with spaces", Err(E::InvalidCharacter { index: 5 })),
        (
            "/repeated//slashes",
            Err(E::RepeatedForwardSlash { index: 10 }),
        ),
        (
            "/9starts_with_number",
            Err(E::TokenStartsWithNumber { index: 1 }),
        ),
        (
            "/starts/42with/number",
            Err(E::TokenStartsWithNumber { index: 8 }),
        ),
        // length is not the first error reported
        (&long, Err(E::NotAbsolute)),
        (&long_absolute, Err(E::TooLong { length: 247 })),
    ];
    for (input, expected) in cases {
        assert_eq!(&Namespace::new(input).map(|_| ()), expected, "{input:?}");
    }
    // rmw's invalid_index for the errors that carry no index
    assert_eq!(E::Empty.invalid_index(), 0);
    assert_eq!(E::NotAbsolute.invalid_index(), 0);
    let too_long = E::TooLong { length: 247 };
    assert_eq!(too_long.invalid_index(), NAMESPACE_MAX_LENGTH - 1);
}

#[test]
fn namespace_limits_and_root() {
    assert_eq!(NAMESPACE_MAX_LENGTH, 245);
    let max = format!("/{}", "a".repeat(NAMESPACE_MAX_LENGTH - 1));
    assert!(Namespace::new(&max).is_ok());
    // longer than a topic may be: still reported as a namespace length error
    let very_long = format!("/{}", "a".repeat(300));
    let expected = Err(NamespaceError::TooLong { length: 301 });
    assert_eq!(Namespace::new(&very_long), expected);
    assert!(Namespace::root().is_root());
    assert_eq!(Namespace::default().as_str(), "/");
    assert_eq!(
        NamespaceError::EndsWithForwardSlash { index: 3 }.to_string(),
        "namespace must not end with a '/', unless only a '/' (index 3)"
    );
}
