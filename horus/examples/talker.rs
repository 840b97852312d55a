//! The demo_nodes_cpp talker as a HORUS node: publishes `std_msgs/msg/String`
//! `Hello World: <n>` on `chatter` once a second, interoperable with ROS 2's
//! `ros2 run demo_nodes_cpp listener`.
//!
//! `talker [--count N] [--ros-args …]`: stops after N messages (default: Ctrl+C). Accepts
//! `--ros-args` as any ROS executable (`-r chatter:=other`, `-r __node:=x`, `-p rate:=10.0`).

use horus::prelude::*;
use horus::StopHandle;

struct Talker {
    chatter: Topic<StringMsg>,
    count: u64,
    limit: Option<u64>,
    stop: StopHandle,
}

impl Node for Talker {
    fn name(&self) -> &str {
        "talker"
    }

    fn tick(&mut self) {
        self.count += 1;
        let data = format!("Hello World: {}", self.count);
        println!("[INFO] [talker]: Publishing: '{data}'");
        hlog!(info, "Publishing: '{}'", data);
        self.chatter.send(StringMsg { data });
        if self.limit.is_some_and(|l| self.count >= l) {
            self.stop.stop();
        }
    }

    fn shutdown(&mut self) -> Result<()> {
        println!("[INFO] [talker]: shut down after {} messages", self.count);
        Ok(())
    }
}

/// `--count N` among the program's own (non-ROS) arguments.
fn count_arg() -> Result<Option<u64>> {
    let args = horus::ros::Arguments::from_process()?.non_ros_args();
    match args.iter().position(|a| a == "--count") {
        Some(i) => {
            let n = args
                .get(i + 1)
                .ok_or_else(|| Error::config("--count needs a number"))?;
            Ok(Some(
                n.parse()
                    .map_err(|e| Error::config(format!("--count {n}: {e}")))?,
            ))
        }
        None => Ok(None),
    }
}

fn main() -> Result<()> {
    let limit = count_arg()?;
    let rate: f64 = std::env::var("TALKER_RATE_HZ")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(1.0);
    let mut sched = Scheduler::new().tick_rate(rate.hz());
    let stop = sched.stop_handle();
    sched
        .add(Talker {
            chatter: Topic::new("chatter")?,
            count: 0,
            limit,
            stop,
        })
        .build()?;
    sched.run()
}
