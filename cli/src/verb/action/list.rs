//! `horus-ros action list` (ros2action `verb/list.py`).

use horus_ros_graph::NamesAndTypes;

use crate::session::GraphSource;
use crate::verb::names;
use crate::{CliError, Global};

/// Arguments of `action list`.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Additionally show the action type.
    #[arg(short = 't', long)]
    pub show_types: bool,
    /// Only display the number of actions discovered.
    #[arg(short = 'c', long)]
    pub count_actions: bool,
}

/// Runs `action list`.
pub fn run(global: &Global, args: &ListArgs) -> Result<(), CliError> {
    let source = GraphSource::open(global)?;
    let actions = source.read(|c| c.action_names_and_types());
    if global.json {
        return names::print_json(&if args.count_actions {
            names::count_json(actions.len())
        } else {
            names::names_and_types_json(&actions)
        });
    }
    print!("{}", render(&actions, args));
    Ok(())
}

/// ros2action's text: the count with `-c`, else one action a line, `/name [types]` with `-t`.
fn render(actions: &NamesAndTypes, args: &ListArgs) -> String {
    if args.count_actions {
        return format!("{}\n", actions.len());
    }
    let mut out = String::new();
    for (name, types) in actions {
        out.push_str(name);
        if args.show_types {
            let types: Vec<&str> = types.iter().map(String::as_str).collect();
            out.push_str(&format!(" [{}]", types.join(", ")));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_as_ros2action_prints_them() {
        let mut actions = NamesAndTypes::new();
        actions.insert(
            "/fibonacci".into(),
            ["test_msgs/action/Fibonacci".into()].into(),
        );
        actions.insert(
            "/b".into(),
            ["p/action/A".into(), "p/action/B".into()].into(),
        );
        let args = |t, c| ListArgs {
            show_types: t,
            count_actions: c,
        };
        assert_eq!(render(&actions, &args(false, false)), "/b\n/fibonacci\n");
        assert_eq!(
            render(&actions, &args(true, false)),
            "/b [p/action/A, p/action/B]\n/fibonacci [test_msgs/action/Fibonacci]\n"
        );
        assert_eq!(render(&actions, &args(true, true)), "2\n");
    }
}
