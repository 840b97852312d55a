//! Actions derived from feedback topics, as rcl_action's `graph.c`.

use super::fixtures::*;
use crate::{filter_action_names, ActionUser, GraphCache, NamesAndTypes, NodeInfo};

const FEEDBACK: &str = "test_msgs::action::dds_::Fibonacci_FeedbackMessage_";
const STATUS: &str = "action_msgs::msg::dds_::GoalStatusArray_";

/// `/fibonacci` served by `/server` (participant `p1`) and used by `/ns/client` (`p2`), next to
/// an ordinary topic.
fn action_graph() -> GraphCache {
    let mut g = GraphCache::new();
    g.add_participant(gid("p1"), Some("/".to_owned()));
    g.add_participant(gid("p2"), Some("/".to_owned()));
    for e in [
        writer("srv_fb", "p1", "rt/fibonacci/_action/feedback", FEEDBACK),
        writer("srv_st", "p1", "rt/fibonacci/_action/status", STATUS),
        writer("srv_chat", "p1", "rt/chatter", STRING),
        reader("cli_fb", "p2", "rt/fibonacci/_action/feedback", FEEDBACK),
        reader("cli_st", "p2", "rt/fibonacci/_action/status", STATUS),
    ] {
        g.add_entity(e);
    }
    g.update_participant_entities(msg(
        "p1",
        vec![node("/", "server", &[], &["srv_fb", "srv_st", "srv_chat"])],
    ));
    g.update_participant_entities(msg(
        "p2",
        vec![node("/ns", "client", &["cli_fb", "cli_st"], &[])],
    ));
    g
}

fn user(namespace: &str, name: &str) -> ActionUser {
    ActionUser {
        node: NodeInfo {
            namespace: namespace.to_owned(),
            name: name.to_owned(),
            enclave: Some("/".to_owned()),
        },
        types: vec!["test_msgs/action/Fibonacci".to_owned()],
    }
}

#[test]
fn actions_are_named_from_feedback_topics() {
    let g = action_graph();
    let actions = g.action_names_and_types();
    assert_eq!(actions.keys().collect::<Vec<_>>(), ["/fibonacci"]);
    assert_eq!(
        actions["/fibonacci"].iter().collect::<Vec<_>>(),
        ["test_msgs/action/Fibonacci"]
    );
}

#[test]
fn servers_publish_feedback_and_clients_subscribe_to_it() {
    let g = action_graph();
    let served = g
        .action_server_names_and_types_by_node("server", "/")
        .expect("node known");
    assert_eq!(served.keys().collect::<Vec<_>>(), ["/fibonacci"]);
    assert!(g
        .action_client_names_and_types_by_node("server", "/")
        .expect("node known")
        .is_empty());
    let used = g
        .action_client_names_and_types_by_node("client", "/ns")
        .expect("node known");
    assert_eq!(used.keys().collect::<Vec<_>>(), ["/fibonacci"]);
    assert!(g
        .action_server_names_and_types_by_node("nobody", "/")
        .is_err());
}

#[test]
fn clients_and_servers_of_one_action() {
    let g = action_graph();
    let found = g.action_clients_and_servers("/fibonacci");
    assert_eq!(found.servers, vec![user("/", "server")]);
    assert_eq!(found.clients, vec![user("/ns", "client")]);
    let none = g.action_clients_and_servers("/other");
    assert!(none.servers.is_empty() && none.clients.is_empty());
}

#[test]
fn filter_cuts_name_and_type_suffixes_as_rcl_action() {
    let mut topics = NamesAndTypes::new();
    topics.insert(
        "/fib/_action/feedback".to_owned(),
        [
            "pkg/action/Fibonacci_FeedbackMessage".to_owned(),
            "pkg/msg/Odd".to_owned(),
        ]
        .into(),
    );
    topics.insert(
        "/chatter".to_owned(),
        ["std_msgs/msg/String".to_owned()].into(),
    );
    let actions = filter_action_names(&topics);
    assert_eq!(actions.len(), 1);
    assert_eq!(
        actions["/fib"].iter().collect::<Vec<_>>(),
        ["pkg/action/Fibonacci", "pkg/msg/Odd"]
    );
}
