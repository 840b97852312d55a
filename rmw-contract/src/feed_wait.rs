//! The discovery feed's blocking wait, one loop for every backend: each backend says how to
//! take a queued event and how to block on its wake-ups ([`FeedBackend`]: mio for rustdds, a
//! waitset for Cyclone); the deadline and the "woken with nothing to report" rule live here
//! once.

use std::time::{Duration, Instant};

use crate::discovery::DiscoveryEvent;
use crate::FeedBackend;

/// The next event of `feed`, waiting for one at most `timeout` (`None`: until one comes or the
/// feed is woken). A wake-up with nothing to report returns `None`; so does a failed wait
/// (logged).
pub fn next_timeout(
    feed: &mut (impl FeedBackend + ?Sized),
    timeout: Option<Duration>,
) -> Option<DiscoveryEvent> {
    let deadline = timeout.and_then(|t| Instant::now().checked_add(t));
    let mut woken = false;
    loop {
        if let Some(event) = feed.try_next() {
            return Some(event);
        }
        let now = Instant::now();
        let left = match deadline {
            Some(d) => match d.checked_duration_since(now) {
                Some(left) if !left.is_zero() => Some(left),
                _ => return None,
            },
            None if woken => return None,
            None => None,
        };
        match feed.wait(left) {
            Ok(reported) => woken |= reported,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => {
                tracing::warn!("waiting for discovery events failed: {e}");
                return None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::VecDeque;
    use std::time::{Duration, Instant};

    use std::sync::Arc;

    use super::next_timeout;
    use crate::discovery::DiscoveryEvent;
    use crate::Gid;
    use crate::{FeedBackend, Wake};

    /// A feed whose waits hand out scripted outcomes, each bringing the events listed.
    #[derive(Default)]
    struct Scripted {
        queued: VecDeque<DiscoveryEvent>,
        waits: VecDeque<(std::io::Result<bool>, Vec<DiscoveryEvent>)>,
        limits: Vec<Option<Duration>>,
    }

    struct NoWake;

    impl Wake for NoWake {
        fn wake(&self) {}
    }

    impl FeedBackend for Scripted {
        fn try_next(&mut self) -> Option<DiscoveryEvent> {
            self.queued.pop_front()
        }
        fn waker(&self) -> Arc<dyn Wake> {
            Arc::new(NoWake)
        }
        fn wait(&mut self, limit: Option<Duration>) -> std::io::Result<bool> {
            self.limits.push(limit);
            let (outcome, events) = self
                .waits
                .pop_front()
                .expect("the loop waited more often than scripted");
            self.queued.extend(events);
            outcome
        }
    }

    fn lost(n: u8) -> DiscoveryEvent {
        DiscoveryEvent::ParticipantLost {
            gid: Gid::from_bytes([n; 16]),
        }
    }

    #[test]
    fn a_queued_event_is_returned_without_waiting() {
        let mut feed = Scripted::default();
        feed.queued.push_back(lost(1));
        assert_eq!(next_timeout(&mut feed, None), Some(lost(1)));
        assert!(feed.limits.is_empty());
    }

    #[test]
    fn without_a_timeout_a_wake_up_with_nothing_to_report_returns_none() {
        let mut feed = Scripted::default();
        feed.waits.push_back((Ok(true), vec![]));
        assert_eq!(next_timeout(&mut feed, None), None);
        assert_eq!(feed.limits, vec![None]);
    }

    #[test]
    fn interrupted_waits_are_retried_and_the_event_they_led_to_is_returned() {
        let mut feed = Scripted::default();
        let interrupted = std::io::Error::from(std::io::ErrorKind::Interrupted);
        feed.waits.push_back((Err(interrupted), vec![]));
        feed.waits.push_back((Ok(true), vec![lost(2)]));
        assert_eq!(next_timeout(&mut feed, None), Some(lost(2)));
        assert_eq!(feed.limits.len(), 2);
    }

    #[test]
    fn a_failed_wait_ends_with_none() {
        let mut feed = Scripted::default();
        let broken = std::io::Error::from(std::io::ErrorKind::BrokenPipe);
        feed.waits.push_back((Err(broken), vec![]));
        assert_eq!(next_timeout(&mut feed, Some(Duration::from_secs(60))), None);
    }

    #[test]
    fn the_wait_is_bounded_by_the_timeout() {
        let mut feed = Scripted::default();
        let timeout = Duration::from_secs(60);
        let before = Instant::now();
        feed.waits.push_back((Ok(true), vec![lost(3)]));
        assert_eq!(next_timeout(&mut feed, Some(timeout)), Some(lost(3)));
        let limit = feed.limits[0].expect("a bounded wait");
        assert!(limit <= timeout && limit + before.elapsed() >= timeout);
    }

    #[test]
    fn a_backend_ending_its_wait_early_is_waited_on_again() {
        // A backend may end a wait with nothing reported (e.g. at its late-joiner retry): that
        // is no wake-up, so an unlimited wait goes on.
        let mut feed = Scripted::default();
        feed.waits.push_back((Ok(false), vec![]));
        feed.waits.push_back((Ok(true), vec![lost(4)]));
        assert_eq!(next_timeout(&mut feed, None), Some(lost(4)));
        assert_eq!(feed.limits, vec![None, None]);
    }
}
