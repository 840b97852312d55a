//! A node that serves the Fibonacci action (`action_tutorials_interfaces/action/Fibonacci`) on
//! `fibonacci` from its `tick` — one step of every goal per tick, with feedback — and, in the
//! same ticks, sends goals to the action named by the parameter `target` (default
//! `/fibonacci`: here, itself), printing their feedback and results. Neither ever blocks the
//! loop. `ros2 action send_goal /fibonacci action_tutorials_interfaces/action/Fibonacci
//! "{order: 5}"` works on it, and it drives ROS 2's `fibonacci_action_server` just as well.
//!
//! `fibonacci_node [--count N] [--ros-args …]`: stops after N results (default: Ctrl+C).

use horus::actions::interfaces::action_tutorials_interfaces::action::{
    Fibonacci, FibonacciFeedback, FibonacciGoal, FibonacciResult,
};
use horus::actions::{
    ActionClient, ClientGoalHandle, PendingGoal, PendingResult, ServerGoalHandle,
};
use horus::current::GoalQueue;
use horus::prelude::*;
use horus::StopHandle;

/// The order of the goals this node sends.
const ORDER: i32 = 5;

/// A goal being executed: its handle and the sequence so far.
struct Executing {
    handle: ServerGoalHandle<Fibonacci>,
    sequence: Vec<i32>,
}

/// Where this node's own goal is.
enum Sending {
    Idle,
    Goal(PendingGoal<Fibonacci>),
    Result(ClientGoalHandle<Fibonacci>, PendingResult<Fibonacci>),
}

struct FibonacciNode {
    server: Option<GoalQueue<Fibonacci>>,
    executing: Vec<Executing>,
    client: Option<ActionClient<Fibonacci>>,
    sending: Sending,
    results: u64,
    limit: Option<u64>,
    stop: StopHandle,
}

impl Node for FibonacciNode {
    fn name(&self) -> &str {
        "fibonacci_node"
    }

    fn init(&mut self) -> Result<()> {
        self.server = Some(horus::current::action_server::<Fibonacci>("fibonacci")?);
        let target = horus::current::parameter_or("target", "/fibonacci".to_owned());
        self.client = Some(horus::current::action_client::<Fibonacci>(&target)?);
        println!("[INFO] [fibonacci_node]: serving fibonacci, sending goals to {target}");
        Ok(())
    }

    fn tick(&mut self) {
        self.serve();
        self.send();
    }
}

impl FibonacciNode {
    /// Takes new goals and moves every goal one step: a feedback, or its end.
    fn serve(&mut self) {
        if let Some(server) = &self.server {
            while let Some(handle) = server.try_recv() {
                println!("[INFO] [fibonacci_node]: Executing goal...");
                self.executing.push(Executing {
                    handle,
                    sequence: vec![0, 1],
                });
            }
        }
        let mut still = Vec::with_capacity(self.executing.len());
        for mut goal in self.executing.drain(..) {
            let order = usize::try_from(goal.handle.goal().order).unwrap_or(0);
            if goal.handle.is_cancel_requested() {
                println!("[INFO] [fibonacci_node]: Goal canceled");
                let sequence = goal.sequence;
                let _ = goal.handle.canceled(FibonacciResult { sequence });
            } else if goal.sequence.len() > order {
                let sequence = goal.sequence;
                let _ = goal.handle.succeed(FibonacciResult { sequence });
            } else {
                let n = goal.sequence.len();
                let next = goal.sequence[n - 1].saturating_add(goal.sequence[n - 2]);
                goal.sequence.push(next);
                let _ = goal.handle.publish_feedback(FibonacciFeedback {
                    partial_sequence: goal.sequence.clone(),
                });
                still.push(goal);
            }
        }
        self.executing = still;
    }

    /// One goal of our own at a time: sent, accepted, its feedback printed, its result.
    fn send(&mut self) {
        let Some(client) = &self.client else {
            return;
        };
        self.sending = match std::mem::replace(&mut self.sending, Sending::Idle) {
            Sending::Idle => {
                let goal = FibonacciGoal { order: ORDER };
                Sending::Goal(client.send_goal_pending(goal, Duration::from_secs(10)))
            }
            Sending::Goal(mut pending) => match pending.try_take() {
                None => Sending::Goal(pending),
                Some(Ok(handle)) => {
                    println!("[INFO] [fibonacci_node]: Goal accepted :)");
                    let result = handle.get_result_pending(Duration::from_secs(60));
                    Sending::Result(handle, result)
                }
                Some(Err(e)) => {
                    hlog!(warn, "goal not accepted: {}", e);
                    Sending::Idle
                }
            },
            Sending::Result(handle, mut result) => {
                while let Some(feedback) = handle.try_recv_feedback() {
                    println!(
                        "[INFO] [fibonacci_node]: Received feedback: {:?}",
                        feedback.partial_sequence
                    );
                }
                match result.try_take() {
                    None => Sending::Result(handle, result),
                    Some(Ok((state, result))) => {
                        println!(
                            "[INFO] [fibonacci_node]: Result: {:?} ({state:?})",
                            result.sequence
                        );
                        self.results += 1;
                        if self.limit.is_some_and(|l| self.results >= l) {
                            self.stop.stop();
                        }
                        Sending::Idle
                    }
                    Some(Err(e)) => {
                        hlog!(warn, "no result: {}", e);
                        Sending::Idle
                    }
                }
            }
        };
    }
}

fn main() -> Result<()> {
    let args = horus::ros::Arguments::from_process()?.non_ros_args();
    let limit = match args.iter().position(|a| a == "--count") {
        Some(i) => Some(
            args.get(i + 1)
                .and_then(|n| n.parse().ok())
                .ok_or_else(|| Error::config("--count needs a number"))?,
        ),
        None => None,
    };
    let mut sched = Scheduler::new().tick_rate(50_u64.hz());
    let stop = sched.stop_handle();
    sched
        .add(FibonacciNode {
            server: None,
            executing: Vec::new(),
            client: None,
            sending: Sending::Idle,
            results: 0,
            limit,
            stop,
        })
        .build()?;
    sched.run()
}
