//! [`Client`]: the rmw side of one service client — its request writer and response reader,
//! sending each request in the convention of the server it goes to (rmw `rmw_send_request`) and
//! taking the responses addressed to it (rmw `rmw_take_response`).

use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::{Mutex, MutexGuard};

use super::{client_id, CycloneHeader, WireFlavour, HORUS_CLIENT_MARKER};
use crate::pubsub::{EndpointError, PublishError, TakeError};
use crate::{Gid, Node, RawEndpointSpec, RawReader, RawWriter, SampleId};

/// rmw_cyclonedds numbers requests with one process-wide counter; so do we.
static NEXT_CYCLONE_SEQ: AtomicI64 = AtomicI64::new(1);

/// A response taken by [`Client::take_response`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TakenResponse {
    /// The convention it came in.
    pub flavour: WireFlavour,
    /// The sequence number of the request it answers (what
    /// [`send_request`](Client::send_request) gave).
    pub sequence_number: i64,
    /// Whether it is a horus-ros server's error reply (its message is then the handler's error
    /// as a CDR string) rather than a response.
    pub failed: bool,
    /// Whether the message is big-endian CDR.
    pub big_endian: bool,
    body: Vec<u8>,
    offset: usize,
}

impl TakenResponse {
    /// The CDR body of the response message (after any rmw_cyclonedds header).
    pub fn message(&self) -> &[u8] {
        self.body.get(self.offset..).unwrap_or_default()
    }
}

/// The rmw side of one service client.
#[derive(Debug)]
pub struct Client {
    requests: Mutex<RawWriter>,
    responses: Mutex<RawReader>,
    request_writer: Gid,
    response_reader: Gid,
    client_id: u64,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Client {
    /// A client of `node` writing requests on `request` and reading responses on `response`.
    /// Its response reader stores only the responses to it where servers send every client's
    /// responses to every client (see [`Node::create_response_reader`]).
    pub fn new(
        node: &Node,
        request: &RawEndpointSpec,
        response: &RawEndpointSpec,
    ) -> Result<Self, EndpointError> {
        let requests = node.create_raw_writer(request)?;
        let id = client_id(requests.gid());
        let responses = node.create_response_reader(response, id)?;
        Ok(Self {
            request_writer: requests.gid(),
            response_reader: responses.gid(),
            client_id: id,
            requests: Mutex::new(requests),
            responses: Mutex::new(responses),
        })
    }

    /// The GID of the request writer.
    pub fn request_writer(&self) -> Gid {
        self.request_writer
    }

    /// The GID of the response reader.
    pub fn response_reader(&self) -> Gid {
        self.response_reader
    }

    /// The id this client puts in rmw_cyclonedds' request header (and announces as
    /// `clientid=` where the backend can).
    pub fn client_id(&self) -> u64 {
        self.client_id
    }

    /// The response reader, to wait on or attach to a wait set. Take responses with
    /// [`take_response`](Self::take_response), not from it.
    pub fn response_reader_mut(&self) -> MutexGuard<'_, RawReader> {
        lock(&self.responses)
    }

    /// rmw `rmw_send_request`: writes `body` (a CDR_LE request body) in `flavour`'s convention;
    /// returns the request's sequence number, which its response carries.
    ///
    /// - rmw_fastrtps: `related_sample_identity` = {our response reader, a mark telling a
    ///   horus-ros server that we take error replies}; the number is the sample's own.
    /// - rmw_cyclonedds: the header {our id, a process-wide number} before the body.
    pub fn send_request(&self, body: &[u8], flavour: WireFlavour) -> Result<i64, PublishError> {
        let requests = lock(&self.requests);
        match flavour {
            WireFlavour::FastRtps => {
                let related = SampleId {
                    writer: self.response_reader,
                    sequence_number: HORUS_CLIENT_MARKER,
                };
                let id = requests.write(body.to_vec(), Some(related), None)?;
                Ok(id.sequence_number)
            }
            WireFlavour::CycloneDds => {
                let seq = NEXT_CYCLONE_SEQ.fetch_add(1, Ordering::Relaxed);
                let header = CycloneHeader {
                    guid: self.client_id,
                    seq,
                };
                requests.write(header.prepend(body), None, None)?;
                Ok(seq)
            }
        }
    }

    /// rmw `rmw_take_response`: the next response addressed to this client, if any (responses
    /// to other clients are dropped on the way). A sample the DDS layer could not decode is an
    /// error; the next call goes on with the following one.
    pub fn take_response(&self) -> Result<Option<TakenResponse>, TakeError> {
        let mut responses = lock(&self.responses);
        while let Some(sample) = responses.take()? {
            if let Some(response) = self.response_from(sample) {
                return Ok(Some(response));
            }
        }
        Ok(None)
    }

    /// Reads `sample` as a response to this client; `None` if it is addressed to another.
    fn response_from(&self, sample: crate::RawSample) -> Option<TakenResponse> {
        let (flavour, sequence, offset) = match sample.related {
            Some(related) => {
                // rmw_fastrtps `__rmw_take_response`: ours iff the related GUID is our reader
                // or writer.
                if related.writer != self.response_reader && related.writer != self.request_writer {
                    return None;
                }
                (WireFlavour::FastRtps, related.sequence_number, 0)
            }
            None => {
                // rmw_cyclonedds `rmw_take_response`: ours iff the header carries our id.
                let (header, message) = CycloneHeader::split(&sample.body, sample.big_endian)?;
                if header.guid != self.client_id {
                    return None;
                }
                let offset = sample.body.len() - message.len();
                (WireFlavour::CycloneDds, header.seq, offset)
            }
        };
        // A negative number is a horus-ros server's error reply to request -sequence.
        Some(TakenResponse {
            flavour,
            sequence_number: sequence.saturating_abs(),
            failed: sequence < 0,
            big_endian: sample.big_endian,
            body: sample.body,
            offset,
        })
    }
}
