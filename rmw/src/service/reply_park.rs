//! Replies that cannot be sent yet, parked per client with bounds, and warnings about peers
//! limited in rate: what keeps one peer from stalling a server or flooding its log.
//!
//! rmw_fastrtps (jazzy `rmw_response.cpp` `__rmw_send_response`, `custom_service_info.hpp`
//! `check_for_subscription`) and rmw_cyclonedds (jazzy `rmw_node.cpp` `rmw_send_response`,
//! `check_for_response_reader`) make a reply wait, on the serving thread, until the client's reply
//! reader is matched: up to the writer's `max_blocking_time` (100 ms) and 100 ms, and only when
//! they know which reader that is (a reader GUID in `related_sample_identity`, a `clientid=` in
//! USER_DATA). A horus-ros server never waits: such a reply is parked here and sent when the graph
//! reports the match, or dropped (debug log) when it is older than [`MAX_AGE`].

use std::collections::{HashMap, VecDeque};
use std::time::{Duration, Instant};

use crate::Gid;

/// How long a parked reply waits for its client's reply reader to be matched before it is
/// dropped: longer than discovery takes between two loaded processes (a reader's announcement can
/// take seconds to be matched), shorter than the timeouts callers usually give.
pub(crate) const MAX_AGE: Duration = Duration::from_secs(5);
/// Most replies parked for one client (one request writer).
pub(crate) const MAX_PER_CLIENT: usize = 64;
/// Most bytes of replies parked for one client (one reply is always admitted).
pub(crate) const MAX_BYTES_PER_CLIENT: usize = 4 << 20;
/// Most replies parked for all clients together.
pub(crate) const MAX_TOTAL: usize = 1024;
/// Most bytes of replies parked for all clients together.
pub(crate) const MAX_TOTAL_BYTES: usize = 64 << 20;

/// One parked item and when it was parked.
struct Parked<T> {
    item: T,
    bytes: usize,
    since: Instant,
}

/// Items (replies) waiting for their client, by client, oldest first, within the bounds above.
pub(crate) struct Park<T> {
    clients: HashMap<Gid, VecDeque<Parked<T>>>,
    count: usize,
    bytes: usize,
}

impl<T> Default for Park<T> {
    fn default() -> Self {
        Self {
            clients: HashMap::new(),
            count: 0,
            bytes: 0,
        }
    }
}

impl<T> Park<T> {
    /// Items parked now, for all clients.
    pub(crate) fn len(&self) -> usize {
        self.count
    }

    /// Whether one more item of `client` fits the bounds (per client: count and bytes; for all
    /// clients: count and bytes). A client with nothing parked always gets one item in, unless
    /// the whole park is full.
    pub(crate) fn admits(&self, client: Gid) -> bool {
        if self.count >= MAX_TOTAL || self.bytes >= MAX_TOTAL_BYTES {
            return false;
        }
        self.clients.get(&client).is_none_or(|q| {
            let bytes: usize = q.iter().map(|p| p.bytes).sum();
            q.len() < MAX_PER_CLIENT && bytes < MAX_BYTES_PER_CLIENT
        })
    }

    /// Parks `item` of `bytes` for `client`; gives it back if it does not fit.
    pub(crate) fn park(&mut self, client: Gid, item: T, bytes: usize) -> Result<(), T> {
        if !self.admits(client) {
            return Err(item);
        }
        self.clients.entry(client).or_default().push_back(Parked {
            item,
            bytes,
            since: Instant::now(),
        });
        self.count += 1;
        self.bytes += bytes;
        Ok(())
    }

    /// Whether anything is parked for `client`.
    pub(crate) fn holds(&self, client: Gid) -> bool {
        self.clients.contains_key(&client)
    }

    /// The oldest item parked for `client`.
    pub(crate) fn first(&self, client: Gid) -> Option<&T> {
        self.clients.get(&client)?.front().map(|p| &p.item)
    }

    /// Takes every item of `client`, oldest first.
    pub(crate) fn take_client(&mut self, client: Gid) -> Vec<T> {
        let Some(queue) = self.clients.remove(&client) else {
            return Vec::new();
        };
        self.count -= queue.len();
        self.bytes -= queue.iter().map(|p| p.bytes).sum::<usize>();
        queue.into_iter().map(|p| p.item).collect()
    }

    /// The clients with something parked.
    pub(crate) fn clients(&self) -> Vec<Gid> {
        self.clients.keys().copied().collect()
    }

    /// Removes and returns the items parked for longer than `max_age` at `now`, with their
    /// clients.
    pub(crate) fn expire(&mut self, now: Instant, max_age: Duration) -> Vec<(Gid, T)> {
        let mut expired = Vec::new();
        self.clients.retain(|client, queue| {
            while queue
                .front()
                .is_some_and(|p| now.duration_since(p.since) >= max_age)
            {
                if let Some(p) = queue.pop_front() {
                    self.count -= 1;
                    self.bytes -= p.bytes;
                    expired.push((*client, p.item));
                }
            }
            !queue.is_empty()
        });
        expired
    }

    /// When the oldest parked item reaches `max_age`, if anything is parked.
    pub(crate) fn next_expiry(&self, max_age: Duration) -> Option<Instant> {
        self.clients
            .values()
            .filter_map(|q| q.front())
            .map(|p| p.since + max_age)
            .min()
    }
}

/// How often one warning is logged per peer and kind at most.
pub(crate) const WARNING_INTERVAL: Duration = Duration::from_secs(10);
/// Most (peer, kind) pairs remembered; beyond, the table starts afresh.
const MAX_WARNED: usize = 1024;

/// What a rate-limited warning is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum WarningKind {
    /// The request cannot be read (too short, undecodable, or a failed handler with no error
    /// reply for this client).
    Malformed,
    /// The request was dropped: the client's parked replies are at their bound.
    Overflow,
}

/// Decides which warnings about peers are logged: the first of each (peer, kind), then at most
/// one per [`WARNING_INTERVAL`], telling how many were held back meanwhile.
#[derive(Default)]
pub(crate) struct PeerWarnings {
    last: HashMap<(Gid, WarningKind), (Instant, u64)>,
}

impl PeerWarnings {
    /// `Some(number held back since the last one logged)` if a warning of `kind` about `peer`
    /// is to be logged now, `None` if it is to be held back.
    pub(crate) fn allow(&mut self, peer: Gid, kind: WarningKind, now: Instant) -> Option<u64> {
        if self.last.len() >= MAX_WARNED && !self.last.contains_key(&(peer, kind)) {
            self.last.clear();
        }
        match self.last.get_mut(&(peer, kind)) {
            Some((at, held)) if now.duration_since(*at) < WARNING_INTERVAL => {
                *held += 1;
                None
            }
            Some((at, held)) => {
                let n = *held;
                *at = now;
                *held = 0;
                Some(n)
            }
            None => {
                self.last.insert((peer, kind), (now, 0));
                Some(0)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gid(n: u8) -> Gid {
        let mut b = [0u8; 16];
        b[15] = n;
        Gid::from_bytes(b)
    }

    #[test]
    fn a_client_gets_at_most_its_share() {
        let mut park = Park::default();
        for i in 0..MAX_PER_CLIENT {
            assert!(park.park(gid(1), i, 10).is_ok());
        }
        assert!(!park.admits(gid(1)));
        assert_eq!(park.park(gid(1), 99, 10), Err(99));
        assert!(park.admits(gid(2)), "other clients are not held back");
        assert_eq!(park.len(), MAX_PER_CLIENT);
        assert_eq!(
            park.take_client(gid(1)),
            (0..MAX_PER_CLIENT).collect::<Vec<_>>()
        );
        assert_eq!(park.len(), 0);
        assert!(!park.holds(gid(1)));
    }

    #[test]
    fn bytes_are_bounded_but_one_big_reply_fits() {
        let mut park = Park::default();
        assert!(park.park(gid(1), 0, MAX_BYTES_PER_CLIENT * 2).is_ok());
        assert!(park.park(gid(1), 1, 1).is_err());
        for c in 2..40 {
            let _ = park.park(gid(c), c as usize, MAX_BYTES_PER_CLIENT * 2);
        }
        assert!(park.bytes >= MAX_TOTAL_BYTES);
        assert!(!park.admits(gid(200)), "the whole park is full");
    }

    #[test]
    fn old_items_expire_in_order() {
        let mut park = Park::default();
        park.park(gid(1), 1, 1).expect("fits");
        park.park(gid(2), 2, 1).expect("fits");
        let now = Instant::now();
        assert!(park.expire(now, MAX_AGE).is_empty());
        assert!(park
            .next_expiry(MAX_AGE)
            .is_some_and(|t| t <= now + MAX_AGE));
        let later = now + MAX_AGE + Duration::from_millis(1);
        let mut gone = park.expire(later, MAX_AGE);
        gone.sort();
        assert_eq!(gone, vec![(gid(1), 1), (gid(2), 2)]);
        assert_eq!((park.len(), park.bytes), (0, 0));
        assert_eq!(park.next_expiry(MAX_AGE), None);
    }

    #[test]
    fn warnings_are_limited_per_peer_and_kind() {
        let mut w = PeerWarnings::default();
        let t = Instant::now();
        assert_eq!(w.allow(gid(1), WarningKind::Overflow, t), Some(0));
        assert_eq!(w.allow(gid(1), WarningKind::Overflow, t), None);
        assert_eq!(w.allow(gid(1), WarningKind::Overflow, t), None);
        assert_eq!(w.allow(gid(1), WarningKind::Malformed, t), Some(0));
        assert_eq!(w.allow(gid(2), WarningKind::Overflow, t), Some(0));
        assert_eq!(
            w.allow(gid(1), WarningKind::Overflow, t + WARNING_INTERVAL),
            Some(2)
        );
    }
}
