use crate::names::{validate_unexpanded_name, UnexpandedNameError};

// Valid cases from ros2/rcl (jazzy, 9.2) rcl/test/rcl/test_validate_topic_name.cpp
// (`normal`, `various_valid_topics`).
#[test]
fn rcl_various_valid_topics() {
    let valid = [
        "topic",
        "foo",
        "abc123",
        "_foo",
        "Foo",
        "BAR",
        "~",
        "foo/bar",
        "~/foo",
        "{foo}_bar",
        "foo/{ping}/bar",
        "foo/_bar",
        "foo_/bar",
        "foo_",
        "/foo",
        "/bar/baz",
        "/_private/thing",
        "/public_namespace/_private/thing",
        "{foo1}",
        "{foo_bar}",
        "{_bar}",
    ];
    for input in valid {
        assert_eq!(validate_unexpanded_name(input), Ok(()), "input {input:?}");
    }
}

// Invalid cases from ros2/rcl (jazzy, 9.2) rcl/test/rcl/test_validate_topic_name.cpp
// (`various_invalid_topics`).
#[test]
fn rcl_various_invalid_topics() {
    use UnexpandedNameError as E;
    let cases = [
        ("123abc", E::TokenStartsWithNumber { index: 0 }),
        ("123", E::TokenStartsWithNumber { index: 0 }),
        (" ", E::InvalidCharacter { index: 0 }),
        ("foo bar", E::InvalidCharacter { index: 3 }),
        ("/~", E::MisplacedTilde { index: 1 }),
        ("~foo", E::TildeNotFollowedByForwardSlash),
        ("foo~", E::MisplacedTilde { index: 3 }),
        ("foo~/bar", E::MisplacedTilde { index: 3 }),
        ("foo/~bar", E::MisplacedTilde { index: 4 }),
        ("foo/~/bar", E::MisplacedTilde { index: 4 }),
        ("foo/", E::EndsWithForwardSlash { index: 3 }),
        ("", E::Empty),
        ("foo/123bar", E::TokenStartsWithNumber { index: 4 }),
        ("foo/bar}/baz", E::UnmatchedCurlyBrace { index: 7 }),
        ("foo/{bar", E::UnmatchedCurlyBrace { index: 4 }),
        ("{$}", E::SubstitutionInvalidCharacter { index: 1 }),
        ("{{bar}_baz}", E::SubstitutionInvalidCharacter { index: 1 }),
        (
            "foo/{bar/baz}",
            E::SubstitutionInvalidCharacter { index: 8 },
        ),
        ("{1foo}", E::SubstitutionStartsWithNumber { index: 1 }),
    ];
    for (input, expected) in cases {
        assert_eq!(validate_unexpanded_name(input), Err(expected), "{input:?}");
    }
    // rcl's invalid_index for the errors that carry no index
    assert_eq!(E::Empty.invalid_index(), 0);
    assert_eq!(E::TildeNotFollowedByForwardSlash.invalid_index(), 1);
}

#[test]
fn rcl_quirks_and_messages() {
    // rcl never looks at the last character in its token loop: "~a" passes.
    assert_eq!(validate_unexpanded_name("~a"), Ok(()));
    // "{}" passes validation; expansion then reports an unknown substitution.
    assert_eq!(validate_unexpanded_name("{}"), Ok(()));
    assert_eq!(
        UnexpandedNameError::Empty.to_string(),
        "topic name must not be empty string"
    );
    assert_eq!(
        UnexpandedNameError::InvalidCharacter { index: 3 }.to_string(),
        "topic name must not contain characters other than alphanumerics, '_', '~', '{', or '}' \
         (index 3)"
    );
}
