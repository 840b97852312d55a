//! The talker as a managed (lifecycle) node, as rclcpp_lifecycle's `lifecycle_talker` demo: it
//! publishes `Hello World: <n>` on `chatter` only while `active`, its topic is created on
//! `configure` and dropped on `cleanup`/`shutdown`. Drive it with `ros2 lifecycle set
//! /managed_talker configure`, then `activate` (or `horus-ros lifecycle set …`).
//!
//! `managed_talker [--ros-args …]` runs until Ctrl+C. `TALKER_RATE_HZ` sets the rate (default 2).

use horus::prelude::*;
use horus::Managed;

struct ManagedTalker {
    chatter: Option<Topic<StringMsg>>,
    count: u64,
}

impl Node for ManagedTalker {
    fn name(&self) -> &str {
        "managed_talker"
    }

    /// On `configure`.
    fn init(&mut self) -> Result<()> {
        self.chatter = Some(Topic::new("chatter")?);
        println!("[INFO] [managed_talker]: on_configure() is called.");
        Ok(())
    }

    /// Only while `active`.
    fn tick(&mut self) {
        let Some(chatter) = &self.chatter else {
            return;
        };
        self.count += 1;
        let data = format!("Hello World: {}", self.count);
        println!("[INFO] [managed_talker]: Lifecycle publisher is active. Publishing: [{data}]");
        chatter.send(StringMsg { data });
    }

    /// On `cleanup` and `shutdown` (and at exit if still configured).
    fn shutdown(&mut self) -> Result<()> {
        self.chatter = None;
        println!("[INFO] [managed_talker]: on_cleanup() is called.");
        Ok(())
    }
}

fn main() -> Result<()> {
    let rate: f64 = std::env::var("TALKER_RATE_HZ")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(2.0);
    let mut sched = Scheduler::new().tick_rate(rate.hz());
    sched
        .add(Managed::new(ManagedTalker {
            chatter: None,
            count: 0,
        }))
        .build()?;
    println!("[INFO] [managed_talker]: ready");
    sched.run()
}
