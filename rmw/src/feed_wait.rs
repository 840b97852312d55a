//! The discovery feed's blocking wait, one loop for both backends: each backend says how to
//! take a queued event and how to block on its DDS layer's wake-ups (mio for rustdds, a
//! waitset for Cyclone); the deadline, the late-joiner retry and the "woken with nothing to
//! report" rule live here once.

use std::time::{Duration, Instant};

use crate::discovery::DiscoveryEvent;
use crate::late_joiner::LateJoinerReader;

/// One backend's discovery feed, as [`next_timeout`] drives it.
pub(crate) trait FeedSource {
    /// The next event, if any (non-blocking; also applies what the last wait gathered and
    /// renews the late-joiner reader when it is due).
    fn try_next(&mut self) -> Option<DiscoveryEvent>;

    /// The late-joiner bookkeeping, for when its reader's retry is due.
    fn late_joiner(&self) -> &LateJoinerReader;

    /// Blocks until the DDS layer reports something or the feed is woken (`Ok(true)`), or
    /// `limit` passes (`Ok(false)`; `None`: no limit), gathering what it reports.
    fn wait(&mut self, limit: Option<Duration>) -> std::io::Result<bool>;
}

/// The next event of `feed`, waiting for one at most `timeout` (`None`: until one comes or the
/// feed is woken). A wake-up with nothing to report returns `None`; so does a failed wait
/// (logged).
pub(crate) fn next_timeout(
    feed: &mut impl FeedSource,
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
        // The late-joiner reader's retry is due at most then (see `crate::late_joiner`).
        let limit = feed.late_joiner().wait_limit(left, now);
        match feed.wait(limit) {
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

    use super::{next_timeout, FeedSource};
    use crate::discovery::DiscoveryEvent;
    use crate::late_joiner::LateJoinerReader;
    use crate::Gid;

    /// A feed whose waits hand out scripted outcomes, each bringing the events listed.
    #[derive(Default)]
    struct Scripted {
        queued: VecDeque<DiscoveryEvent>,
        waits: VecDeque<(std::io::Result<bool>, Vec<DiscoveryEvent>)>,
        limits: Vec<Option<Duration>>,
        late_joiner: LateJoinerReader,
    }

    impl FeedSource for Scripted {
        fn try_next(&mut self) -> Option<DiscoveryEvent> {
            self.queued.pop_front()
        }
        fn late_joiner(&self) -> &LateJoinerReader {
            &self.late_joiner
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
    fn a_due_late_joiner_retry_bounds_an_unlimited_wait() {
        let mut feed = Scripted::default();
        // A writer of `ros_discovery_info` (entity kind 0x03) whose sample is awaited.
        let mut writer = [7u8; 16];
        writer[12..].copy_from_slice(&[0, 0, 1, 0x03]);
        feed.late_joiner.writer_discovered(Gid::from_bytes(writer));
        let _ = feed.late_joiner.action(false, Instant::now());
        // The wait ends at the retry (nothing reported), then the next one is woken.
        feed.waits.push_back((Ok(false), vec![]));
        feed.waits.push_back((Ok(true), vec![lost(4)]));
        assert_eq!(next_timeout(&mut feed, None), Some(lost(4)));
        let first = feed.limits[0].expect("bounded by the retry");
        assert!(first <= crate::late_joiner::FIRST_RETRY);
    }
}
