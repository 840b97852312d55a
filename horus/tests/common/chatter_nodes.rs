//! demo_nodes' talker and listener as HORUS nodes (shared by the tests that run them;
//! `#[path]`-included where the rest of `common` is not needed).

use std::sync::mpsc;

use horus::prelude::*;

/// Publishes `Hello World: <n>` on `chatter` (resolved in its node's namespace, remapped by
/// `--ros-args`), one message a tick; logs its `rate` parameter at init.
pub struct Talker {
    chatter: Topic<StringMsg>,
    count: u64,
}

impl Talker {
    /// A talker that has sent nothing yet.
    pub fn on_chatter() -> Self {
        Self {
            chatter: Topic::new("chatter").expect("topic"),
            count: 0,
        }
    }
}

impl Node for Talker {
    fn name(&self) -> &str {
        "talker"
    }
    fn init(&mut self) -> Result<()> {
        let rate: i64 = horus::current::parameter_or("rate", 0);
        hlog!(info, "talker starting, rate parameter {rate}");
        Ok(())
    }
    fn tick(&mut self) {
        self.count += 1;
        self.chatter.send(StringMsg {
            data: format!("Hello World: {}", self.count),
        });
    }
}

/// Forwards what it hears on `chatter` (resolved in its node's namespace, remapped by
/// `--ros-args`).
pub struct Listener {
    chatter: Topic<StringMsg>,
    heard: mpsc::Sender<String>,
}

impl Listener {
    /// A listener whose messages arrive on `heard`.
    pub fn new(heard: mpsc::Sender<String>) -> Self {
        Self {
            chatter: Topic::new("chatter").expect("topic"),
            heard,
        }
    }
}

impl Node for Listener {
    fn name(&self) -> &str {
        "listener"
    }
    fn init(&mut self) -> Result<()> {
        self.chatter.connect_subscriber()?;
        Ok(())
    }
    fn tick(&mut self) {
        while let Some(m) = self.chatter.try_recv() {
            let _ = self.heard.send(m.data);
        }
    }
}
