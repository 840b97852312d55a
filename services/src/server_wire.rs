//! [`ServerWire`]: what every server ([`ServiceServer`](crate::ServiceServer),
//! [`DdsServiceServer`](crate::DdsServiceServer), the async server) reads requests and writes
//! responses through — rmw's [`Server`], learning of its clients from the graph, which wakes the
//! serving thread when a change may let parked responses go out.

use std::ops::Deref;
use std::sync::Arc;

use horus_ros_graph::{GraphView, GraphWatcher};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::service::{Server, WireFlavour};
use horus_ros_rmw::{Gid, RawReaderWaker};

use crate::runtime::Runtime;

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

impl Deref for ServerWire {
    type Target = Server;

    fn deref(&self) -> &Server {
        &self.server
    }
}
