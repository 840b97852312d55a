//! [`ServerWire`]: what every server ([`ServiceServer`](crate::ServiceServer),
//! [`DdsServiceServer`](crate::DdsServiceServer), the async server) reads requests and writes
//! responses through — rmw's [`Server`], learning of its clients from the graph, which wakes the
//! serving thread when a change may let parked responses go out.

use std::ops::Deref;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use horus_ros_graph::{GraphView, GraphWatcher};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::service::{Request, Server, TakenRequest, WireFlavour};
use horus_ros_rmw::{Gid, RawReader, RawReaderWaker};

use crate::runtime::Runtime;

/// Most samples dropped (undecodable, or no request to answer) in one drain before the thread
/// checks whether to stop.
const MAX_ERRORS_PER_DRAIN: usize = 1000;

/// What a server's request thread does with the requests [`ServerWire::serve`] takes: every
/// server (blocking, async, [`DdsServiceServer`](crate::DdsServiceServer)) takes its requests in
/// that one loop.
pub(crate) trait Serve {
    /// Whether another request may be taken now (default: always). At a bound, requests stay in
    /// the reader: what makes room must wake the thread (the reader's waker).
    fn has_room(&self) -> bool {
        true
    }

    /// Handles one request taken.
    fn request(&mut self, request: Request);

    /// After each drain of the reader: sends the parked replies whose client can hear them now
    /// and drops the old ones; returns when the next one expires.
    fn drained(&mut self) -> Option<Instant>;
}

/// Wakes a server's thread when the graph changes while responses are parked (their clients'
/// readers may have been matched): the thread then calls
/// [`Server::flush_parked`].
struct ParkWatch {
    server: Arc<Server>,
    waker: RawReaderWaker,
}

impl GraphWatcher for ParkWatch {
    fn graph_changed(&self, _graph: &GraphView<'_>) {
        if self.server.parked() > 0 {
            self.waker.wake();
        }
    }
}

/// rmw's [`Server`] for one service, with the graph watch that wakes its thread.
pub(crate) struct ServerWire {
    server: Arc<Server>,
    /// Kept alive while the server is (the graph holds it weakly).
    _watch: Arc<ParkWatch>,
}

impl ServerWire {
    /// The server of `service` replying with `reply_writer`, every client taken to follow
    /// `flavour` if given (else its DDS vendor's convention); `waker` wakes the thread that
    /// serves it, which then calls [`Server::flush_parked`].
    pub(crate) fn new(
        runtime: &Runtime,
        service: ServiceName,
        reply_writer: Gid,
        flavour: Option<WireFlavour>,
        waker: RawReaderWaker,
    ) -> Self {
        let server = Arc::new(Server::new(
            Arc::clone(&runtime.graph) as Arc<dyn horus_ros_rmw::service::Peers>,
            service,
            reply_writer,
            flavour,
            (
                runtime.node.context().capabilities(),
                runtime.node.context().vendor_id(),
            ),
        ));
        let watch = Arc::new(ParkWatch {
            server: Arc::clone(&server),
            waker,
        });
        let weak: std::sync::Weak<dyn GraphWatcher> = Arc::downgrade(&watch) as _;
        runtime.graph.watch(weak);
        Self {
            server,
            _watch: watch,
        }
    }
}

impl ServerWire {
    /// The request thread's loop, until `stop` is set: takes the requests of `requests` while
    /// `server` has room and hands each to it, lets it flush its parked replies after each
    /// drain, then waits on the reader — woken at once by a request, by the reader's waker (a
    /// stop, room made) and by graph changes while replies are parked; with none parked, nothing
    /// else can change, so the only time limit is the earliest parked reply's expiry.
    pub(crate) fn serve(
        &self,
        requests: &mut RawReader,
        stop: &AtomicBool,
        server: &mut impl Serve,
    ) {
        while !stop.load(Ordering::SeqCst) {
            let mut errors = 0;
            // Whether the drain stopped at its error bound with requests possibly left behind.
            let mut cut_short = false;
            while server.has_room() {
                match self.take_request(requests) {
                    TakenRequest::Request(request) => server.request(request),
                    TakenRequest::Empty => break,
                    TakenRequest::Dropped => {
                        errors += 1;
                        if errors >= MAX_ERRORS_PER_DRAIN {
                            cut_short = true;
                            break;
                        }
                    }
                }
            }
            let next_expiry = server.drained();
            if cut_short {
                // Wake-ups are edge-triggered: what is left would not wake us.
                continue;
            }
            requests.wait(next_expiry.map(|t| t.saturating_duration_since(Instant::now())));
        }
    }
}

impl Deref for ServerWire {
    type Target = Server;

    fn deref(&self) -> &Server {
        &self.server
    }
}
