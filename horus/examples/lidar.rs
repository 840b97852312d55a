//! The Node API's standard sensor node: a lidar driver publishing `sensor_msgs/msg/LaserScan`
//! on `scan`, on a simulated serial device (no hardware needed). The port comes from the
//! parameter `port` (`--ros-args -p port:=/dev/ttyUSB0`); the port `/dev/missing` cannot be
//! opened, which shows the restart policy at work.

use horus::prelude::*;

/// A simulated serial lidar: a rotating wall at 2 m, with a bump that moves each scan.
struct SerialPort {
    port: String,
    scans: u32,
}

/// A device error.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct DeviceError(String);

impl SerialPort {
    fn open(port: &str) -> std::result::Result<Self, DeviceError> {
        if port == "/dev/missing" {
            return Err(DeviceError(format!("cannot open {port}: no such device")));
        }
        Ok(Self {
            port: port.to_owned(),
            scans: 0,
        })
    }

    fn read_scan(&mut self) -> std::result::Result<LaserScan, DeviceError> {
        self.scans += 1;
        let n = 360;
        let bump = (self.scans as usize) % n;
        let ranges = (0..n).map(|i| if i == bump { 1.0 } else { 2.0 }).collect();
        Ok(LaserScan {
            header: Header {
                stamp: Time::default(),
                frame_id: "laser".to_owned(),
            },
            angle_min: -std::f32::consts::PI,
            angle_max: std::f32::consts::PI,
            angle_increment: 2.0 * std::f32::consts::PI / n as f32,
            time_increment: 0.0,
            scan_time: 0.1,
            range_min: 0.1,
            range_max: 10.0,
            ranges,
            intensities: Vec::new(),
        })
    }

    fn stop_motor(&mut self) -> std::result::Result<(), DeviceError> {
        println!("[INFO] [lidar]: motor of {} stopped", self.port);
        Ok(())
    }
}

struct LidarNode {
    scan_pub: Topic<LaserScan>,
    device: Option<SerialPort>,
    port: String,
}

impl LidarNode {
    fn new(port: &str) -> Result<Self> {
        Ok(Self {
            scan_pub: Topic::new("scan")?,
            device: None,
            port: port.to_string(),
        })
    }
}

impl Node for LidarNode {
    fn name(&self) -> &str {
        "lidar"
    }

    fn init(&mut self) -> Result<()> {
        self.port = horus::current::parameter_or("port", self.port.clone());
        self.device = Some(SerialPort::open(&self.port)?);
        hlog!(info, "Lidar connected on {}", self.port);
        println!("[INFO] [lidar]: connected on {}", self.port);
        Ok(())
    }

    fn tick(&mut self) {
        if let Some(ref mut dev) = self.device {
            if let Ok(scan) = dev.read_scan() {
                self.scan_pub.send(scan);
            }
        }
    }

    fn shutdown(&mut self) -> Result<()> {
        if let Some(ref mut dev) = self.device {
            dev.stop_motor()?;
        }
        hlog!(info, "Lidar stopped");
        Ok(())
    }
}

fn main() -> Result<()> {
    let mut sched = Scheduler::new().tick_rate(10_u64.hz());
    sched
        .add(LidarNode::new("/dev/ttyUSB0")?)
        .order(0)
        .failure_policy(FailurePolicy::Restart {
            max_restarts: 3,
            initial_backoff: 1_u64.ms(),
        })
        .build()?;
    sched.run()
}
