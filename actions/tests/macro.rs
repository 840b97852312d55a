//! `action!` gives the same types as the interface generator does from the `.action` file (whose
//! hashes `tests/interfaces.rs` and the Jazzy tests check against rosidl's): names, RIHS01
//! hashes of the action and of every derived type, and the bytes on the wire.

use horus_ros_actions::interfaces::test_msgs::action as generated;
use horus_ros_actions::Action;
use horus_ros_msgs::{cdr, Message, Service};

mod defined {
    horus_ros_actions::action! {
        /// test_msgs' Fibonacci, written in Rust.
        test_msgs/Fibonacci {
            goal { order: i32 }
            result { sequence: Vec<i32> }
            feedback { sequence: Vec<i32> }
        }
    }
}

#[test]
fn names_and_hashes_equal_the_generated_ones() {
    assert_eq!(
        defined::Fibonacci::TYPE_NAME,
        generated::Fibonacci::TYPE_NAME
    );
    assert_eq!(
        defined::Fibonacci::type_hash(),
        generated::Fibonacci::type_hash()
    );
    let pairs = [
        (
            defined::FibonacciGoal::TYPE_NAME,
            defined::FibonacciGoal::type_hash(),
            generated::FibonacciGoal::type_hash(),
        ),
        (
            defined::FibonacciResult::TYPE_NAME,
            defined::FibonacciResult::type_hash(),
            generated::FibonacciResult::type_hash(),
        ),
        (
            defined::FibonacciFeedback::TYPE_NAME,
            defined::FibonacciFeedback::type_hash(),
            generated::FibonacciFeedback::type_hash(),
        ),
        (
            defined::FibonacciSendGoalRequest::TYPE_NAME,
            defined::FibonacciSendGoalRequest::type_hash(),
            generated::FibonacciSendGoalRequest::type_hash(),
        ),
        (
            defined::FibonacciSendGoalResponse::TYPE_NAME,
            defined::FibonacciSendGoalResponse::type_hash(),
            generated::FibonacciSendGoalResponse::type_hash(),
        ),
        (
            defined::FibonacciGetResultRequest::TYPE_NAME,
            defined::FibonacciGetResultRequest::type_hash(),
            generated::FibonacciGetResultRequest::type_hash(),
        ),
        (
            defined::FibonacciGetResultResponse::TYPE_NAME,
            defined::FibonacciGetResultResponse::type_hash(),
            generated::FibonacciGetResultResponse::type_hash(),
        ),
        (
            defined::FibonacciFeedbackMessage::TYPE_NAME,
            defined::FibonacciFeedbackMessage::type_hash(),
            generated::FibonacciFeedbackMessage::type_hash(),
        ),
        (
            defined::FibonacciSendGoal::TYPE_NAME,
            defined::FibonacciSendGoal::type_hash(),
            generated::FibonacciSendGoal::type_hash(),
        ),
        (
            defined::FibonacciGetResult::TYPE_NAME,
            defined::FibonacciGetResult::type_hash(),
            generated::FibonacciGetResult::type_hash(),
        ),
    ];
    for (name, ours, theirs) in pairs {
        assert_eq!(ours, theirs, "{name}");
    }
    assert_eq!(
        defined::FibonacciSendGoalRequest::TYPE_NAME,
        "test_msgs/action/Fibonacci_SendGoal_Request"
    );
}

#[test]
fn the_wire_bytes_equal_the_generated_ones() {
    let id = [7u8; 16];
    let ours = defined::Fibonacci::create_goal_request(id, defined::FibonacciGoal { order: 9 });
    let theirs =
        generated::Fibonacci::create_goal_request(id, generated::FibonacciGoal { order: 9 });
    assert_eq!(
        cdr::to_cdr(&ours).expect("encodes"),
        cdr::to_cdr(&theirs).expect("encodes")
    );
    let feedback = defined::Fibonacci::create_feedback_message(
        id,
        defined::FibonacciFeedback {
            sequence: vec![0, 1, 1],
        },
    );
    let bytes = cdr::to_cdr(&feedback).expect("encodes");
    let back: generated::FibonacciFeedbackMessage = cdr::from_cdr(&bytes).expect("decodes");
    assert_eq!(
        generated::Fibonacci::split_feedback_message(back)
            .1
            .sequence,
        [0, 1, 1]
    );
    let response = defined::Fibonacci::create_result_response(
        4,
        defined::FibonacciResult {
            sequence: vec![0, 1],
        },
    );
    let (status, result) = defined::Fibonacci::split_result_response(response);
    assert_eq!((status, result.sequence), (4, vec![0, 1]));
}
