use crate::names::{ServiceName, TopicName, TopicNameError, TOPIC_NAME_MAX_LENGTH};

// Cases from ros2/rmw (jazzy) rmw/test/test_validate_full_topic_name.cpp.
#[test]
fn rmw_test_validate_full_topic_name() {
    use TopicNameError as E;
    let long = "a".repeat(TOPIC_NAME_MAX_LENGTH + 1);
    let long_absolute = format!("/{long}");
    let cases: &[(&str, Result<(), E>)] = &[
        ("/basename_only", Ok(())),
        ("/with_one/namespace", Ok(())),
        ("", Err(E::Empty)),
        ("not_absolute", Err(E::NotAbsolute)),
        ("not/absolute", Err(E::NotAbsolute)),
        ("/ends/with/", Err(E::EndsWithForwardSlash { index: 10 })),
        ("/", Err(E::EndsWithForwardSlash { index: 0 })),
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
        (&long_absolute, Err(E::TooLong { length: 249 })),
    ];
    for (input, expected) in cases {
        assert_eq!(&TopicName::new(input).map(|_| ()), expected, "{input:?}");
        // services follow the same rules
        assert_eq!(&ServiceName::new(input).map(|_| ()), expected, "{input:?}");
    }
    // rmw's invalid_index for the errors that carry no index
    assert_eq!(E::Empty.invalid_index(), 0);
    assert_eq!(E::NotAbsolute.invalid_index(), 0);
    let too_long = E::TooLong { length: 249 };
    assert_eq!(too_long.invalid_index(), TOPIC_NAME_MAX_LENGTH - 1);
}

#[test]
fn topic_name_limits_and_messages() {
    assert_eq!(TOPIC_NAME_MAX_LENGTH, 247);
    let max = format!("/{}", "a".repeat(TOPIC_NAME_MAX_LENGTH - 1));
    assert!(TopicName::new(&max).is_ok());
    let over = format!("/{}", "a".repeat(TOPIC_NAME_MAX_LENGTH));
    let expected = Err(TopicNameError::TooLong { length: 248 });
    assert_eq!(TopicName::new(&over), expected);
    // a non-ASCII byte is reported at its byte offset, as in C
    let expected = Err(TopicNameError::InvalidCharacter { index: 4 });
    assert_eq!(TopicName::new("/caf\u{e9}"), expected);
    assert_eq!(
        TopicNameError::NotAbsolute.to_string(),
        "topic name must be absolute, it must lead with a '/'"
    );
    assert_eq!(
        TopicNameError::TooLong { length: 300 }.to_string(),
        "topic length should not exceed '247' (length 300)"
    );
}
