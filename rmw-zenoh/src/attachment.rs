//! The attachment rmw_zenoh puts on every sample, query and reply (rmw_zenoh_cpp 0.2.10
//! `src/detail/attachment_helpers.cpp`; wire facts §4): the zenoh-ext serialization of
//! `(int64 sequence_number, int64 source_timestamp, uint8[16] gid)`, 33 bytes.
//!
//! ```text
//! 8 bytes  sequence number, little-endian
//! 8 bytes  source timestamp, ns since the UNIX epoch, little-endian
//! 1 byte   0x10: the LEB128 length (16) of the GID array
//! 16 bytes the GID of the sender's liveliness token
//! ```

use horus_ros_rmw_contract::Gid;

/// Its length in bytes.
pub(crate) const ATTACHMENT_LEN: usize = 33;

/// One sample's attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Attachment {
    /// The sender's sequence number (each publisher's starts at 1).
    pub(crate) sequence_number: i64,
    /// When it was sent, in ns since the UNIX epoch.
    pub(crate) source_timestamp: i64,
    /// The sender's GID.
    pub(crate) gid: Gid,
}

/// Why an attachment could not be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub(crate) enum AttachmentError {
    /// It has another length than 33 bytes.
    #[error("attachment of {0} bytes (rmw_zenoh's has 33)")]
    Length(usize),
    /// The GID array's length is not 16.
    #[error("attachment GID length {0} (rmw_zenoh's is 16)")]
    GidLength(u8),
}

impl Attachment {
    /// The 33 bytes.
    pub(crate) fn to_bytes(self) -> [u8; ATTACHMENT_LEN] {
        let mut b = [0u8; ATTACHMENT_LEN];
        b[..8].copy_from_slice(&self.sequence_number.to_le_bytes());
        b[8..16].copy_from_slice(&self.source_timestamp.to_le_bytes());
        b[16] = 16;
        b[17..].copy_from_slice(self.gid.as_bytes());
        b
    }

    /// Reads the 33 bytes.
    pub(crate) fn parse(b: &[u8]) -> Result<Self, AttachmentError> {
        let b: &[u8; ATTACHMENT_LEN] =
            b.try_into().map_err(|_| AttachmentError::Length(b.len()))?;
        if b[16] != 16 {
            return Err(AttachmentError::GidLength(b[16]));
        }
        let mut seq = [0u8; 8];
        seq.copy_from_slice(&b[..8]);
        let mut ts = [0u8; 8];
        ts.copy_from_slice(&b[8..16]);
        let mut gid = [0u8; 16];
        gid.copy_from_slice(&b[17..]);
        Ok(Self {
            sequence_number: i64::from_le_bytes(seq),
            source_timestamp: i64::from_le_bytes(ts),
            gid: Gid::from_bytes(gid),
        })
    }
}

/// Now, in ns since the UNIX epoch (rmw_zenoh's `source_timestamp`).
pub(crate) fn now_ns() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hex(s: &str) -> Vec<u8> {
        (0..s.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex"))
            .collect()
    }

    #[test]
    fn the_talkers_first_attachment_reads_and_writes_back() {
        // Wire facts §4: talker /chatter #1.
        let wire = hex("0100000000000000ee81be81f767eb1810a003d727012b114c73383c3eccc7e619");
        let a = Attachment::parse(&wire).expect("parses");
        assert_eq!(a.sequence_number, 1);
        assert_eq!(a.source_timestamp, 1_795_643_189_168_603_630);
        assert_eq!(
            a.gid.as_bytes().to_vec(),
            hex("a003d727012b114c73383c3eccc7e619")
        );
        assert_eq!(a.to_bytes().to_vec(), wire);
    }

    #[test]
    fn other_lengths_are_refused() {
        assert_eq!(
            Attachment::parse(&[0; 32]),
            Err(AttachmentError::Length(32))
        );
        assert_eq!(Attachment::parse(&[]), Err(AttachmentError::Length(0)));
        let mut b = [0u8; 33];
        b[16] = 15;
        assert_eq!(Attachment::parse(&b), Err(AttachmentError::GidLength(15)));
    }
}
