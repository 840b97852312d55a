//! What waits for a route: the graph learns of a subscription or a server from its liveliness
//! token, which can reach this session before the subscriber's or queryable's declaration has
//! given it a route (over another link: the router's, or a peer's own); Zenoh then drops the
//! sample or query, where a DDS writer delivers to every matched reader. A publisher or client
//! holds what it writes in that window — bounded in number and in age — and sends it, in order,
//! when its matching listener reports a route ([`RouteWait::on_matching`]).

use std::collections::VecDeque;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use horus_ros_rmw_contract::push::lock;

/// How long an item is held for a route: the window between a token and its route is a few
/// messages long; an item older than this is dropped when the route appears.
pub(crate) const HELD_LIFETIME: Duration = Duration::from_secs(5);

/// Items of type `T` held while there is no route, oldest first.
pub(crate) struct RouteWait<T> {
    state: Mutex<Held<T>>,
    /// Most items held: beyond, the oldest is dropped.
    capacity: usize,
    /// What is held, for the debug log lines of what is dropped.
    what: &'static str,
}

struct Held<T> {
    /// Whether the last matching status reported a route.
    matching: bool,
    items: VecDeque<(T, Instant)>,
}

impl<T> RouteWait<T> {
    /// At most `capacity` (at least 1) held `what`s.
    pub(crate) fn new(capacity: usize, what: &'static str) -> Self {
        Self {
            state: Mutex::new(Held {
                matching: false,
                items: VecDeque::new(),
            }),
            capacity: capacity.max(1),
            what,
        }
    }

    /// Sends `item` now when there is a route, or when `wait` says nothing is waited for; else
    /// holds it. Held under the same lock as the flush, so items go in the order written.
    pub(crate) fn send_or_hold<E>(
        &self,
        item: T,
        wait: impl FnOnce() -> bool,
        send: impl FnOnce(T) -> Result<(), E>,
    ) -> Result<(), E> {
        let mut state = lock(&self.state);
        if state.matching || !wait() {
            return send(item);
        }
        if state.items.len() >= self.capacity {
            state.items.pop_front();
            tracing::debug!(
                "zenoh: a {} dropped: no route (too many waiting)",
                self.what
            );
        }
        state.items.push_back((item, Instant::now()));
        Ok(())
    }

    /// The matching status changed: with a route, what is held goes, in order (what is older
    /// than [`HELD_LIFETIME`] is dropped).
    pub(crate) fn on_matching<E: std::fmt::Display>(
        &self,
        matching: bool,
        mut send: impl FnMut(T) -> Result<(), E>,
    ) {
        let mut state = lock(&self.state);
        state.matching = matching;
        if !matching {
            return;
        }
        for (item, held_since) in std::mem::take(&mut state.items) {
            if held_since.elapsed() > HELD_LIFETIME {
                tracing::debug!("zenoh: a {} dropped: no route in time", self.what);
                continue;
            }
            if let Err(e) = send(item) {
                tracing::debug!("zenoh: a held {} could not be sent: {e}", self.what);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_until_a_route_then_sent_in_order_and_bounded() {
        let wait = RouteWait::new(2, "sample");
        let sent = std::cell::RefCell::new(Vec::new());
        let send = |i: u32| {
            sent.borrow_mut().push(i);
            Ok::<_, String>(())
        };
        // Nothing waited for: sent at once.
        wait.send_or_hold(0, || false, send).expect("sent");
        for i in 1..=3 {
            wait.send_or_hold(i, || true, send).expect("held");
        }
        assert_eq!(*sent.borrow(), [0]);
        wait.on_matching(false, send);
        assert_eq!(*sent.borrow(), [0]);
        // The oldest went beyond the capacity of 2.
        wait.on_matching(true, send);
        assert_eq!(*sent.borrow(), [0, 2, 3]);
        wait.send_or_hold(4, || true, send).expect("sent");
        assert_eq!(*sent.borrow(), [0, 2, 3, 4]);
    }
}
