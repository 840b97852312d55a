//! The demo_nodes_cpp listener as a HORUS node: prints every `std_msgs/msg/String` on `chatter`
//! as `I heard: [<data>]`; interoperable with `ros2 run demo_nodes_cpp talker`.
//!
//! `listener [--count N] [--ros-args …]`: stops after N messages (default: Ctrl+C).

use horus::prelude::*;
use horus::StopHandle;

struct Listener {
    chatter: Topic<StringMsg>,
    heard: u64,
    limit: Option<u64>,
    stop: StopHandle,
}

impl Node for Listener {
    fn name(&self) -> &str {
        "listener"
    }

    fn init(&mut self) -> Result<()> {
        // Subscribe now: messages sent from here on are heard.
        self.chatter.connect_subscriber()?;
        println!("[INFO] [listener]: listening");
        Ok(())
    }

    fn tick(&mut self) {
        while let Some(m) = self.chatter.try_recv() {
            self.heard += 1;
            println!("[INFO] [listener]: I heard: [{}]", m.data);
            hlog!(info, "I heard: [{}]", m.data);
            if self.limit.is_some_and(|l| self.heard >= l) {
                self.stop.stop();
                return;
            }
        }
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
    let mut sched = Scheduler::new().tick_rate(100_u64.hz());
    let stop = sched.stop_handle();
    sched
        .add(Listener {
            chatter: Topic::new("chatter")?,
            heard: 0,
            limit,
            stop,
        })
        .build()?;
    sched.run()
}
