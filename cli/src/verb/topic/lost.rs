//! Lost samples of a subscription, counted from the writers' sequence numbers: the message-lost
//! event that rclpy's `SubscriptionEventCallbacks(message_lost=…)` reports
//! (`rmw_message_lost_status_t`: `total_count`, `total_count_change`), as Fast DDS counts
//! `SAMPLE_LOST`: a sample whose sequence number skips some after the writer's previous one
//! stands for that many lost samples.
//!
//! The first sample of a writer only sets where that writer stands (what it wrote before is not
//! counted). Samples whose sequence number the DDS layer does not report
//! ([`SampleId::UNKNOWN_SEQUENCE_NUMBER`]: the Cyclone backend) count nothing.

use std::collections::HashMap;

use horus_ros_rmw::{Gid, SampleId};

/// How many writers are remembered; past it the one heard from least recently is forgotten
/// (writers that come and go must not grow the map).
const MAX_WRITERS: usize = 1024;

/// rmw's `rmw_message_lost_status_t` after a sample revealed a loss.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LostStatus {
    /// Samples lost since the previous report.
    pub total_count_change: u64,
    /// Samples lost since the subscription was created.
    pub total_count: u64,
}

impl LostStatus {
    /// What ros2topic echo's `_message_lost_event_callback` prints (ros2topic 0.32.2
    /// `verb/echo.py` lines 318-324: `print('A message was lost!!!\n\ttotal count change:'
    /// f'{…total_count_change}' f'\n\ttotal count: {…total_count}', end='---\n')`), without the
    /// final newline.
    pub fn text(&self) -> String {
        format!(
            "A message was lost!!!\n\ttotal count change:{}\n\ttotal count: {}---",
            self.total_count_change, self.total_count
        )
    }
}

/// The last sequence number seen from each writer, and the samples lost so far.
#[derive(Debug, Default)]
pub struct LostSamples {
    /// Per writer: its last sequence number and when it was last heard from (a tick).
    writers: HashMap<Gid, (i64, u64)>,
    tick: u64,
    total: u64,
}

impl LostSamples {
    /// Counts the sample `id`: `Some` with the new status if samples of its writer were skipped
    /// since the previous one.
    pub fn observe(&mut self, id: SampleId) -> Option<LostStatus> {
        if id.sequence_number == SampleId::UNKNOWN_SEQUENCE_NUMBER {
            return None;
        }
        self.tick += 1;
        let previous = self.writers.get(&id.writer).map(|&(seq, _)| seq);
        if previous.is_none() && self.writers.len() >= MAX_WRITERS {
            if let Some(oldest) = self
                .writers
                .iter()
                .min_by_key(|(_, &(_, tick))| tick)
                .map(|(gid, _)| *gid)
            {
                self.writers.remove(&oldest);
            }
        }
        // A sample older than the last one (e.g. a reordered best-effort sample) moves nothing.
        let last = previous.map_or(id.sequence_number, |p| p.max(id.sequence_number));
        self.writers.insert(id.writer, (last, self.tick));
        let skipped = id.sequence_number - previous? - 1;
        if skipped <= 0 {
            return None;
        }
        let change = u64::try_from(skipped).ok()?;
        self.total += change;
        Some(LostStatus {
            total_count_change: change,
            total_count: self.total,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn id(writer: u8, sequence_number: i64) -> SampleId {
        let mut b = [0u8; 16];
        b[0] = writer;
        SampleId {
            writer: Gid::from_bytes(b),
            sequence_number,
        }
    }

    #[test]
    fn gaps_per_writer_are_lost_samples() {
        let mut lost = LostSamples::default();
        assert_eq!(
            lost.observe(id(1, 5)),
            None,
            "the first sample sets the base"
        );
        assert_eq!(lost.observe(id(1, 6)), None);
        assert_eq!(lost.observe(id(2, 1)), None, "another writer");
        assert_eq!(
            lost.observe(id(1, 9)),
            Some(LostStatus {
                total_count_change: 2,
                total_count: 2
            })
        );
        assert_eq!(lost.observe(id(1, 8)), None, "late, not lost");
        assert_eq!(lost.observe(id(1, 10)), None, "9 was the last");
        assert_eq!(
            lost.observe(id(2, 3)),
            Some(LostStatus {
                total_count_change: 1,
                total_count: 3
            })
        );
        assert_eq!(lost.observe(id(3, SampleId::UNKNOWN_SEQUENCE_NUMBER)), None);
        assert_eq!(lost.observe(id(3, SampleId::UNKNOWN_SEQUENCE_NUMBER)), None);
    }

    #[test]
    fn the_writers_remembered_are_bounded() {
        let mut lost = LostSamples::default();
        for n in 0..MAX_WRITERS + 10 {
            let mut b = [0u8; 16];
            b[..8].copy_from_slice(&(n as u64).to_le_bytes());
            lost.observe(SampleId {
                writer: Gid::from_bytes(b),
                sequence_number: 1,
            });
        }
        assert_eq!(lost.writers.len(), MAX_WRITERS);
    }

    #[test]
    fn the_report_is_ros2topic_echos() {
        let s = LostStatus {
            total_count_change: 2,
            total_count: 7,
        };
        assert_eq!(
            s.text(),
            "A message was lost!!!\n\ttotal count change:2\n\ttotal count: 7---"
        );
    }
}
