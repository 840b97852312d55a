//! What the two DDS backends can do and announce, for tests of the conventions that run on
//! neither: the capabilities and vendor of a context on each (the backends' own crates say the
//! same; horus-ros-rmw-implementation's tests check that they do).

use crate::{Backend, Capabilities, VendorId};

/// The capabilities and vendor id of a context on `backend` (RustDDS or Cyclone DDS).
pub(crate) fn of(backend: Backend) -> (Capabilities, VendorId) {
    match backend {
        Backend::RustDds => (Capabilities::NONE.with_sample_identity(), VendorId::RUSTDDS),
        Backend::Cyclone => (
            Capabilities::NONE
                .with_user_data_announced()
                .with_participant_user_data_read()
                .with_type_hashes_announced(),
            VendorId::CYCLONE_DDS,
        ),
        other => panic!("not a DDS backend: {other}"),
    }
}

/// The capabilities of a context on `backend`.
pub(crate) fn capabilities(backend: Backend) -> Capabilities {
    of(backend).0
}
