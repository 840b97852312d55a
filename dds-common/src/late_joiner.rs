//! [`LateJoinerReader`]: when to announce one more `ros_discovery_info` reader so that a peer's
//! transient-local sample reaches us at once instead of at its writer's next periodic heartbeat.
//!
//! Why (seen in RTPS captures against Fast DDS 2.9; Fast DDS 2.14's `StatefulWriter` is the
//! same): a Fast DDS writer sends a matched reliable reader one HEARTBEAT as soon as it learns of
//! the reader (`StatefulWriter::matched_reader_add`), and late-joiner samples only when that
//! reader NACKs them. Our reader learns of the writer through SEDP, usually *after* that
//! heartbeat arrived, so the heartbeat is dropped (the writer was not matched yet). The reader
//! then sends the pre-emptive ACKNACK both rustdds and Cyclone DDS send on a match, with
//! `bitmapBase = 1`; Fast DDS answers a pre-emptive ACKNACK with a heartbeat only when
//! `bitmapBase = 0` (`StatefulWriter::process_acknack`: the `sn_set.base() == 0` branch calls
//! `send_heartbeat_to_nts`), and for `bitmapBase = 1` merely restarts its periodic heartbeat
//! timer (3 s by default, `WriterTimes::heartbeatPeriod`). So the sample waits up to 3 s.
//!
//! What the protocol allows instead: a reader announced *after* we discovered the writer is
//! matched with it before the writer can hear of the reader, so the writer's first heartbeat
//! to it is answered and the sample follows within a round trip. The feed therefore keeps one
//! extra "late-joiner" reader while some discovered `ros_discovery_info` writer has not
//! delivered yet, announced anew whenever such a writer is discovered, and dropped once every
//! awaited participant has been heard. This type is the bookkeeping; each backend owns the
//! reader itself.
//!
//! The new reader can still lose that race: the DDS layer may announce it (SEDP) before it has
//! matched the writer, and a loaded machine widens the gap. The writer's heartbeat to it is then
//! dropped too, and the sample waits for the next periodic one. So while a participant stays
//! awaited the reader is renewed again, after [`FIRST_RETRY`] and then twice as long each time,
//! at most [`MAX_RETRIES`] times; past that the periodic heartbeats deliver (each retry costs
//! one reader and its SEDP announcement).
//!
//! [`LateJoiner`] does the rest of the handling both DDS feeds share: it feeds the bookkeeping
//! from the discovery events, takes the `ros_discovery_info` samples of the feed's readers, and
//! announces, renews or drops the extra reader through the backend's [`InfoReaderSource`],
//! which holds only the backend's DDS calls.

use std::collections::{BTreeSet, VecDeque};
use std::fmt::Display;
use std::time::{Duration, Instant};

use horus_ros_msgs::rmw_dds_common::ParticipantEntitiesInfo;

use crate::discovery::{DiscoveredEndpoint, DiscoveryEvent};
use crate::qos::EndpointKind;
use crate::{Gid, VendorId};

/// Most `ros_discovery_info` samples taken from one reader in one go (the rest come with the
/// feed's next drain: a feed drains whenever nothing is pending).
pub const MAX_INFO_SAMPLES: usize = 4096;

/// Most participants awaited at once: past this, more are not tracked (their samples still
/// come, at the writer's next heartbeat), so a flood of discovered writers cannot grow us.
pub const MAX_AWAITED: usize = 1024;

/// How long a new reader is given before it is renewed again (a handshake takes a round trip).
pub const FIRST_RETRY: Duration = Duration::from_secs(1);

/// Most renewals of a reader that was not answered, before the periodic heartbeats are left to
/// deliver: 1 + 2 + 4 + 8 + 16 s.
pub const MAX_RETRIES: u32 = 5;

/// Participants (by GUID prefix) whose `ros_discovery_info` writer is known but whose sample
/// has not arrived, and whether the current late-joiner reader was announced after all of them.
#[derive(Debug, Default)]
pub struct LateJoinerReader {
    awaited: BTreeSet<[u8; 12]>,
    /// Participants already heard from (their later writers need no new reader).
    heard: BTreeSet<[u8; 12]>,
    /// Whether a writer was discovered after the current reader (if any) was announced.
    stale: bool,
    /// When the current reader is renewed if some participant is still awaited.
    retry_at: Option<Instant>,
    /// Renewals since the last writer was discovered.
    retries: u32,
}

/// What the backend should do with its late-joiner reader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Nothing to change.
    Keep,
    /// Announce a new reader (dropping the old one, which the new one covers).
    Renew,
    /// Drop the reader: nothing is awaited.
    Drop,
}

impl LateJoinerReader {
    /// `participant` was discovered, made by `vendor`. Only Fast DDS writers need the reader
    /// (see the module): Cyclone DDS and rustdds writers answer a reader's pre-emptive ACKNACK
    /// with what it lacks, so their participants are never awaited. Announcing readers no more
    /// often than needed matters on rustdds 0.15, where creating a reader while a burst of
    /// discoveries fills its notification channel can deadlock it (`add_local_reader` sends on
    /// the full channel holding the discovery database's read lock; the reader's creation
    /// waits for the write lock; the event loop that would drain the channel waits behind it).
    pub fn participant_discovered(&mut self, participant: Gid, vendor: VendorId) {
        if vendor != VendorId::FAST_DDS {
            self.heard(participant);
        }
    }

    /// A remote `ros_discovery_info` writer of `participant` was discovered.
    pub fn writer_discovered(&mut self, participant: Gid) {
        let prefix = participant.prefix();
        if self.heard.contains(&prefix) || self.awaited.len() >= MAX_AWAITED {
            return;
        }
        // Discovery reports a writer again on every update of its SEDP data: only a newly
        // awaited participant needs a new reader (rustdds queues at most 4 reader removals).
        if self.awaited.insert(prefix) {
            self.stale = true;
        }
    }

    /// A `ros_discovery_info` sample of `participant` arrived.
    pub fn heard(&mut self, participant: Gid) {
        let prefix = participant.prefix();
        self.awaited.remove(&prefix);
        if self.heard.len() < MAX_AWAITED {
            self.heard.insert(prefix);
        }
    }

    /// `participant` left: forget it.
    pub fn participant_lost(&mut self, participant: Gid) {
        let prefix = participant.prefix();
        self.awaited.remove(&prefix);
        self.heard.remove(&prefix);
    }

    /// What to do with the reader at `now` (`has_reader`: whether one exists); call after a
    /// batch of events, so that a burst of discoveries renews the reader once, and at
    /// the instant its retry is due.
    pub fn action(&mut self, has_reader: bool, now: Instant) -> Action {
        if self.awaited.is_empty() {
            self.stale = false;
            self.retry_at = None;
            return if has_reader {
                Action::Drop
            } else {
                Action::Keep
            };
        }
        if self.stale || !has_reader {
            self.stale = false;
            self.retries = 0;
            self.retry_at = now.checked_add(FIRST_RETRY);
            return Action::Renew;
        }
        match self.retry_at {
            Some(at) if now >= at => {
                self.retries += 1;
                self.retry_at = if self.retries < MAX_RETRIES {
                    now.checked_add(FIRST_RETRY.saturating_mul(1 << self.retries))
                } else {
                    None
                };
                Action::Renew
            }
            _ => Action::Keep,
        }
    }

    /// When [`action`](Self::action) will renew the reader if nothing else happens first.
    #[cfg(test)]
    pub fn retry_at(&self) -> Option<Instant> {
        self.retry_at
    }

    /// How long a feed waiting at `now` at most `left` (`None`: no limit) may wait before it
    /// must call [`action`](Self::action) again (when the reader's retry is due).
    pub fn wait_limit(&self, left: Option<Duration>, now: Instant) -> Option<Duration> {
        let retry = self.retry_at.map(|at| at.saturating_duration_since(now));
        [left, retry].into_iter().flatten().min()
    }

    /// How many participants are awaited.
    #[cfg(test)]
    pub fn awaited(&self) -> usize {
        self.awaited.len()
    }
}

/// One take from a `ros_discovery_info` reader.
#[derive(Debug)]
pub enum Taken {
    /// A sample.
    Sample(ParticipantEntitiesInfo),
    /// A sample that could not be used (the backend logged why); the reader may hold more.
    Skipped,
    /// Nothing more to take now (or the reader failed; the backend logged why).
    End,
}

/// A backend's DDS calls for its `ros_discovery_info` readers: what [`LateJoiner`] needs to
/// announce, watch, retire and read them.
pub trait InfoReaderSource {
    /// The backend's `ros_discovery_info` reader.
    type Reader;
    /// Why [`create`](Self::create) failed.
    type CreateError: Display;
    /// Why [`attach`](Self::attach) failed.
    type AttachError: Display;

    /// Announces a new reader of the topic (with the QoS and USER_DATA of the feed's own).
    fn create(&mut self) -> Result<Self::Reader, Self::CreateError>;

    /// Makes `reader`'s arriving samples wake the feed.
    fn attach(&mut self, reader: &mut Self::Reader) -> Result<(), Self::AttachError>;

    /// Stops `reader`'s samples waking the feed (before it is dropped).
    fn detach(&mut self, reader: &mut Self::Reader);

    /// Takes `reader`'s next sample.
    fn take(reader: &mut Self::Reader) -> Taken;
}

/// Whether `e` is another participant's `ros_discovery_info` writer.
fn is_remote_info_writer(e: &DiscoveredEndpoint, own_gid: Gid) -> bool {
    e.kind == EndpointKind::Writer
        && e.dds_topic_name == super::discovery_info::TOPIC_NAME
        && e.gid.prefix() != own_gid.prefix()
}

/// A DDS feed's late-joiner reader (of type `R`) and its bookkeeping ([`LateJoinerReader`]).
#[derive(Debug)]
pub struct LateJoiner<R> {
    /// The extra reader, while one is announced.
    reader: Option<R>,
    state: LateJoinerReader,
    /// Our own participant's GID: its samples and endpoints are not awaited.
    own_gid: Gid,
}

impl<R> LateJoiner<R> {
    /// No reader yet, nothing awaited; `own_gid` is the feed's participant.
    pub fn new(own_gid: Gid) -> Self {
        Self {
            reader: None,
            state: LateJoinerReader::default(),
            own_gid,
        }
    }

    /// Updates the bookkeeping with a discovery event the feed reports.
    pub fn observe(&mut self, event: &DiscoveryEvent) {
        match event {
            DiscoveryEvent::EndpointDiscovered(e) if is_remote_info_writer(e, self.own_gid) => {
                self.state.writer_discovered(e.participant_gid)
            }
            DiscoveryEvent::ParticipantLost { gid } => self.state.participant_lost(*gid),
            DiscoveryEvent::ParticipantDiscovered(p) => {
                self.state.participant_discovered(p.gid, p.vendor_id)
            }
            _ => {}
        }
    }

    /// Takes the samples of the feed's own `ros_discovery_info` reader `main`, then of the
    /// late-joiner reader, into `pending`.
    pub fn take_all<S>(&mut self, main: &mut R, pending: &mut VecDeque<DiscoveryEvent>)
    where
        S: InfoReaderSource<Reader = R>,
    {
        take_info::<S>(main, self.own_gid, &mut self.state, pending);
        if let Some(late) = self.reader.as_mut() {
            take_info::<S>(late, self.own_gid, &mut self.state, pending);
        }
    }

    /// Announces, renews or drops the reader as [`LateJoinerReader::action`] says at `now`;
    /// samples the old reader already holds are taken into `pending` before it goes.
    pub fn update<S>(
        &mut self,
        source: &mut S,
        pending: &mut VecDeque<DiscoveryEvent>,
        now: Instant,
    ) where
        S: InfoReaderSource<Reader = R>,
    {
        match self.state.action(self.reader.is_some(), now) {
            Action::Keep => {}
            Action::Drop => self.retire(source, pending),
            Action::Renew => {
                self.retire(source, pending);
                match source.create() {
                    Ok(mut reader) => match source.attach(&mut reader) {
                        Ok(()) => self.reader = Some(reader),
                        Err(e) => tracing::debug!(
                            "could not watch a late-joiner ros_discovery_info reader: {e}"
                        ),
                    },
                    // Without it the samples still come, at the writers' next heartbeat.
                    Err(e) => tracing::debug!(
                        "could not create a late-joiner ros_discovery_info reader: {e}"
                    ),
                }
            }
        }
    }

    /// Detaches and drops the reader, taking the samples it already holds first.
    fn retire<S>(&mut self, source: &mut S, pending: &mut VecDeque<DiscoveryEvent>)
    where
        S: InfoReaderSource<Reader = R>,
    {
        if let Some(mut old) = self.reader.take() {
            source.detach(&mut old);
            take_info::<S>(&mut old, self.own_gid, &mut self.state, pending);
        }
    }

    /// The reader, if one is announced (for a feed detaching it as it closes).
    pub fn reader_mut(&mut self) -> Option<&mut R> {
        self.reader.as_mut()
    }

    /// How long a feed waiting at `now` at most `left` may wait (see
    /// [`LateJoinerReader::wait_limit`]).
    pub fn wait_limit(&self, left: Option<Duration>, now: Instant) -> Option<Duration> {
        self.state.wait_limit(left, now)
    }
}

/// Takes at most [`MAX_INFO_SAMPLES`] `ros_discovery_info` samples from `reader` into
/// `pending`, noting each participant heard.
fn take_info<S: InfoReaderSource>(
    reader: &mut S::Reader,
    own_gid: Gid,
    state: &mut LateJoinerReader,
    pending: &mut VecDeque<DiscoveryEvent>,
) {
    for _ in 0..MAX_INFO_SAMPLES {
        match S::take(reader) {
            // As rmw_dds_common's reader (ignore_local_publications): skip our own, which the
            // context reports itself.
            Taken::Sample(info) if info.gid == own_gid => {}
            Taken::Sample(info) => {
                state.heard(info.gid);
                pending.push_back(DiscoveryEvent::ParticipantEntities(info));
            }
            Taken::Skipped => {}
            Taken::End => return,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use super::{Action, LateJoinerReader, FIRST_RETRY, MAX_AWAITED, MAX_RETRIES};
    use crate::Gid;
    use crate::VendorId;

    fn now() -> Instant {
        Instant::now()
    }

    fn participant(n: u8) -> Gid {
        let mut b = [0u8; 16];
        b[0] = 1;
        b[11] = n;
        b[12..].copy_from_slice(&[0, 0, 1, 0xc1]);
        Gid::from_bytes(b)
    }

    fn writer_of(n: u8) -> Gid {
        let mut b = *participant(n).as_bytes();
        b[12..].copy_from_slice(&[0, 0, 1, 0x03]);
        Gid::from_bytes(b)
    }

    #[test]
    fn a_discovered_writer_renews_the_reader_until_its_sample_arrives() {
        let mut l = LateJoinerReader::default();
        assert_eq!(l.action(false, now()), Action::Keep, "nothing awaited");
        l.writer_discovered(writer_of(1));
        assert_eq!(l.action(false, now()), Action::Renew);
        assert_eq!(
            l.action(true, now()),
            Action::Keep,
            "the new reader covers it"
        );
        l.writer_discovered(writer_of(2));
        assert_eq!(
            l.action(true, now()),
            Action::Renew,
            "a reader announced before writer 2 was known may miss its heartbeat"
        );
        l.heard(participant(1));
        assert_eq!(
            l.action(true, now()),
            Action::Keep,
            "participant 2 is still awaited"
        );
        l.heard(participant(2));
        assert_eq!(l.action(true, now()), Action::Drop);
        assert_eq!(l.action(false, now()), Action::Keep);
    }

    #[test]
    fn a_writer_reported_again_renews_nothing() {
        let mut l = LateJoinerReader::default();
        l.writer_discovered(writer_of(1));
        assert_eq!(l.action(false, now()), Action::Renew);
        l.writer_discovered(writer_of(1));
        assert_eq!(
            l.action(true, now()),
            Action::Keep,
            "an update of a known writer"
        );
    }

    #[test]
    fn heard_participants_and_lost_ones_need_no_reader() {
        let mut l = LateJoinerReader::default();
        l.heard(participant(1));
        l.writer_discovered(writer_of(1));
        assert_eq!(l.action(false, now()), Action::Keep, "already heard");
        l.writer_discovered(writer_of(2));
        assert_eq!(l.action(false, now()), Action::Renew);
        l.participant_lost(participant(2));
        assert_eq!(l.action(true, now()), Action::Drop);
        // A participant that left and came back (same prefix) is awaited again.
        l.participant_lost(participant(1));
        l.writer_discovered(writer_of(1));
        assert_eq!(l.action(false, now()), Action::Renew);
    }

    #[test]
    fn a_burst_renews_once_and_the_set_is_bounded() {
        let mut l = LateJoinerReader::default();
        for n in 0..=255u8 {
            l.writer_discovered(writer_of(n));
        }
        assert_eq!(l.action(false, now()), Action::Renew);
        assert_eq!(l.action(true, now()), Action::Keep);
        let mut b = [0u8; 16];
        for i in 0..(MAX_AWAITED as u32 + 10) {
            b[..4].copy_from_slice(&i.to_be_bytes());
            b[4] = 7;
            l.writer_discovered(Gid::from_bytes(b));
        }
        assert_eq!(l.awaited(), MAX_AWAITED);
    }

    #[test]
    fn only_fast_dds_participants_are_awaited() {
        let mut state = LateJoinerReader::default();
        let cyclone = Gid::from_bytes([1; 16]);
        let fast = Gid::from_bytes([2; 16]);
        state.participant_discovered(cyclone, VendorId::CYCLONE_DDS);
        state.participant_discovered(fast, VendorId::FAST_DDS);
        state.writer_discovered(cyclone);
        assert_eq!(state.awaited(), 0);
        assert_eq!(state.action(false, now()), Action::Keep);
        state.writer_discovered(fast);
        assert_eq!(state.awaited(), 1);
        assert_eq!(state.action(false, now()), Action::Renew);
    }

    #[test]
    fn an_unanswered_reader_is_renewed_with_backoff_then_left_to_the_heartbeats() {
        let mut l = LateJoinerReader::default();
        let t0 = Instant::now();
        l.writer_discovered(writer_of(1));
        assert_eq!(l.action(false, t0), Action::Renew);
        assert_eq!(l.retry_at(), Some(t0 + FIRST_RETRY));
        assert_eq!(
            l.wait_limit(None, t0),
            Some(FIRST_RETRY),
            "the feed wakes for it"
        );
        let short = FIRST_RETRY / 4;
        assert_eq!(l.wait_limit(Some(short), t0), Some(short));
        assert_eq!(l.action(true, t0 + FIRST_RETRY / 2), Action::Keep);
        let mut at = t0 + FIRST_RETRY;
        let mut wait = FIRST_RETRY;
        for retry in 1..=MAX_RETRIES {
            assert_eq!(l.action(true, at), Action::Renew, "retry {retry}");
            wait *= 2;
            if retry < MAX_RETRIES {
                assert_eq!(l.retry_at(), Some(at + wait), "retry {retry}");
                at += wait;
            }
        }
        assert_eq!(l.retry_at(), None, "no more retries");
        assert_eq!(l.action(true, at + wait * 10), Action::Keep);
        // A writer discovered later starts a new schedule.
        l.writer_discovered(writer_of(2));
        let later = at + wait * 10;
        assert_eq!(l.action(true, later), Action::Renew);
        assert_eq!(l.retry_at(), Some(later + FIRST_RETRY));
        // Once every awaited participant is heard, nothing is scheduled.
        l.heard(participant(1));
        l.heard(participant(2));
        assert_eq!(l.action(true, later), Action::Drop);
        assert_eq!(l.retry_at(), None);
    }
}
