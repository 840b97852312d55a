//! The Node API's safety-critical node: a differential-drive motor controller. Reads
//! `horus_ros/msg/CmdVel` on `cmd_vel`, publishes `horus_ros/msg/MotorCommand` on `motor.cmd`
//! (the ROS topic `motor/cmd`), with a watchdog, a budget, a deadline with `Miss::SafeMode`, and
//! zeroes the motors on shutdown (Ctrl+C / SIGTERM) and in its safe state. The motors are
//! simulated: the commands are the output.

use horus::prelude::*;

message! {
    /// A velocity command (horus_ros/msg/CmdVel).
    CmdVel { linear: f32, angular: f32 }

    /// Wheel speeds (horus_ros/msg/MotorCommand).
    MotorCommand { left_rpm: f32, right_rpm: f32 }
}

impl MotorCommand {
    fn zero() -> Self {
        Self {
            left_rpm: 0.0,
            right_rpm: 0.0,
        }
    }
}

struct MotorController {
    cmd_sub: Topic<CmdVel>,
    motor_pub: Topic<MotorCommand>,
    safe_mode: bool,
    wheel_base: f32,
}

impl MotorController {
    fn new() -> Result<Self> {
        Ok(Self {
            cmd_sub: Topic::new("cmd_vel")?,
            motor_pub: Topic::new("motor.cmd")?,
            safe_mode: false,
            wheel_base: 0.3,
        })
    }
}

impl Node for MotorController {
    fn name(&self) -> &str {
        "motor_controller"
    }

    fn init(&mut self) -> Result<()> {
        self.cmd_sub.connect_subscriber()?;
        println!("[INFO] [motor_controller]: ready");
        Ok(())
    }

    fn tick(&mut self) {
        if self.safe_mode {
            // Ticked again: the scheduler saw `is_safe_state()` and let the node resume.
            self.safe_mode = false;
            hlog!(info, "Leaving the safe state");
        }
        if let Some(cmd) = self.cmd_sub.try_recv() {
            let command = MotorCommand {
                left_rpm: (cmd.linear - cmd.angular * self.wheel_base / 2.0) * 100.0,
                right_rpm: (cmd.linear + cmd.angular * self.wheel_base / 2.0) * 100.0,
            };
            println!(
                "[INFO] [motor_controller]: left {} rpm, right {} rpm",
                command.left_rpm, command.right_rpm
            );
            self.motor_pub.send(command);
        }
    }

    fn shutdown(&mut self) -> Result<()> {
        self.motor_pub.send(MotorCommand::zero());
        hlog!(info, "Motors zeroed");
        println!("[INFO] [motor_controller]: Motors zeroed");
        Ok(())
    }

    fn enter_safe_state(&mut self) {
        self.motor_pub.send(MotorCommand::zero());
        self.safe_mode = true;
        hlog!(warn, "Safe state — motors zeroed");
    }

    fn is_safe_state(&self) -> bool {
        // The simulated motors stop at once.
        true
    }

    fn on_error(&mut self, error: &str) {
        hlog!(error, "Motor error: {}", error);
        self.enter_safe_state();
    }
}

fn main() -> Result<()> {
    let mut sched = Scheduler::new()
        .tick_rate(100_u64.hz())
        .watchdog(500_u64.ms());

    sched
        .add(MotorController::new()?)
        .order(1)
        .rate(100_u64.hz())
        .budget(200_u64.us())
        .deadline(900_u64.us())
        .on_miss(Miss::SafeMode)
        .build()?;

    sched.run()
}
