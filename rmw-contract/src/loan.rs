//! Loans: a writer lends the buffer a sample's body is written into in place, and a reader lends
//! a received sample's body in place, so that a backend with memory of its own (Zenoh's shared
//! memory) moves a message without copying it on either side. rmw draws the same line:
//! `rmw_borrow_loaned_message` / `rmw_publish_loaned_message` and `rmw_take_loaned_message` /
//! `rmw_return_loaned_message_from_subscription`.
//!
//! Every backend lends: by default a [`WriteLoan`] is a heap buffer that
//! [`WriterBackend::write_loan`](crate::WriterBackend::write_loan) hands to
//! [`write`](crate::WriterBackend::write) as it is, and a [`LoanedSample`] holds what
//! [`take`](crate::ReaderBackend::take) returned; a backend with buffers of its own lends those
//! instead ([`LoanedBuffer`], [`LentBody`]).

use std::any::Any;
use std::ops::{Deref, DerefMut};

use crate::{RawSample, SampleId};

/// A buffer of a backend's own that it lends for one sample: the body's bytes, written in place.
pub trait LoanedBuffer: Send {
    /// The body's bytes (after whatever header the backend keeps in front of them).
    fn body(&self) -> &[u8];
    /// The body's bytes, to be filled.
    fn body_mut(&mut self) -> &mut [u8];
    /// The buffer as its backend's own type, for [`write_loan`](crate::WriterBackend::write_loan)
    /// to take it back.
    fn into_any(self: Box<Self>) -> Box<dyn Any>;
}

/// A received body that its backend lends (e.g. a view of a shared-memory buffer): read in place,
/// given back when dropped.
pub trait LentBody: Send + Sync {
    /// The body's bytes (after the 4-byte encapsulation header).
    fn body(&self) -> &[u8];
}

/// The buffer a writer lends for one sample's CDR body: exactly as long as asked, filled in place
/// (through `DerefMut<Target = [u8]>`), then written with
/// [`WriterBackend::write_loan`](crate::WriterBackend::write_loan) of the writer that lent it.
pub struct WriteLoan(Lent);

enum Lent {
    Heap(Vec<u8>),
    Backend(Box<dyn LoanedBuffer>),
}

impl WriteLoan {
    /// A zeroed heap buffer of `len` bytes (what a backend without buffers of its own lends).
    pub fn heap(len: usize) -> Self {
        Self(Lent::Heap(vec![0; len]))
    }

    /// A buffer of the backend's own.
    pub fn backend(buffer: Box<dyn LoanedBuffer>) -> Self {
        Self(Lent::Backend(buffer))
    }

    /// Whether the buffer is a backend's own rather than the heap's.
    pub fn is_backend_buffer(&self) -> bool {
        matches!(self.0, Lent::Backend(_))
    }

    /// The heap buffer, or the backend's buffer back.
    pub fn into_inner(self) -> Result<Vec<u8>, Box<dyn LoanedBuffer>> {
        match self.0 {
            Lent::Heap(body) => Ok(body),
            Lent::Backend(buffer) => Err(buffer),
        }
    }
}

impl Deref for WriteLoan {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match &self.0 {
            Lent::Heap(body) => body,
            Lent::Backend(buffer) => buffer.body(),
        }
    }
}

impl DerefMut for WriteLoan {
    fn deref_mut(&mut self) -> &mut [u8] {
        match &mut self.0 {
            Lent::Heap(body) => body,
            Lent::Backend(buffer) => buffer.body_mut(),
        }
    }
}

impl std::fmt::Debug for WriteLoan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WriteLoan")
            .field("len", &self.len())
            .field("backend_buffer", &self.is_backend_buffer())
            .finish()
    }
}

/// A sample taken as a loan: its body read in place (through `Deref<Target = [u8]>`), and what
/// a [`RawSample`] says of it besides.
pub struct LoanedSample {
    body: Body,
    /// Whether the body is big-endian (CDR_BE) rather than little-endian.
    pub big_endian: bool,
    /// The sample's own identity (writer GID and sequence number).
    pub id: SampleId,
    /// The `related_sample_identity` it carried, if any.
    pub related: Option<SampleId>,
    /// The writer's local instance handle, where the backend has one.
    pub publication_handle: Option<u64>,
    /// The writer's source timestamp, nanoseconds since the Unix epoch.
    pub source_timestamp: Option<i64>,
    /// When the backend handed the sample over, nanoseconds since the Unix epoch.
    pub received_timestamp: i64,
}

enum Body {
    Owned(Vec<u8>),
    Lent(Box<dyn LentBody>),
}

impl LoanedSample {
    /// A sample whose body its backend lends; the rest as `meta` says (its body is ignored).
    pub fn lent(body: Box<dyn LentBody>, meta: RawSample) -> Self {
        Self {
            body: Body::Lent(body),
            ..Self::from(meta)
        }
    }

    /// Whether the body is lent by the backend (read in place) rather than owned.
    pub fn is_lent(&self) -> bool {
        matches!(self.body, Body::Lent(_))
    }
}

impl From<RawSample> for LoanedSample {
    /// A sample that owns its body (what a backend that lends nothing gives).
    fn from(sample: RawSample) -> Self {
        Self {
            body: Body::Owned(sample.body),
            big_endian: sample.big_endian,
            id: sample.id,
            related: sample.related,
            publication_handle: sample.publication_handle,
            source_timestamp: sample.source_timestamp,
            received_timestamp: sample.received_timestamp,
        }
    }
}

impl Deref for LoanedSample {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match &self.body {
            Body::Owned(body) => body,
            Body::Lent(body) => body.body(),
        }
    }
}

impl std::fmt::Debug for LoanedSample {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoanedSample")
            .field("len", &self.len())
            .field("lent", &self.is_lent())
            .field("id", &self.id)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Gid;

    struct Buffer(Vec<u8>);

    impl LoanedBuffer for Buffer {
        fn body(&self) -> &[u8] {
            &self.0[4..]
        }
        fn body_mut(&mut self) -> &mut [u8] {
            &mut self.0[4..]
        }
        fn into_any(self: Box<Self>) -> Box<dyn Any> {
            self
        }
    }

    impl LentBody for Buffer {
        fn body(&self) -> &[u8] {
            &self.0[4..]
        }
    }

    #[test]
    fn a_loan_is_filled_in_place_and_given_back_as_it_was_lent() {
        let mut heap = WriteLoan::heap(3);
        heap.copy_from_slice(b"abc");
        assert_eq!(heap.into_inner().ok(), Some(b"abc".to_vec()));

        let mut own = WriteLoan::backend(Box::new(Buffer(vec![9; 7])));
        assert!(own.is_backend_buffer());
        assert_eq!(own.len(), 3);
        own.copy_from_slice(b"xyz");
        let back = own.into_inner().expect_err("the backend's buffer");
        let back = back.into_any().downcast::<Buffer>().expect("a Buffer");
        assert_eq!(back.0, b"\x09\x09\x09\x09xyz");
    }

    #[test]
    fn a_loaned_sample_reads_its_body_in_place() {
        let meta = RawSample {
            body: Vec::new(),
            big_endian: false,
            id: SampleId {
                writer: Gid::from_bytes([1; 16]),
                sequence_number: 7,
            },
            related: None,
            publication_handle: None,
            source_timestamp: Some(5),
            received_timestamp: 6,
        };
        let lent = LoanedSample::lent(Box::new(Buffer(b"hdr:body".to_vec())), meta.clone());
        assert!(lent.is_lent());
        assert_eq!(&*lent, b"body");
        assert_eq!(lent.id, meta.id);
        let owned = LoanedSample::from(RawSample {
            body: b"owned".to_vec(),
            ..meta
        });
        assert!(!owned.is_lent());
        assert_eq!(&*owned, b"owned");
        assert_eq!(owned.source_timestamp, Some(5));
    }
}
