//! Enclaves: a context announces its own (`/` unless set); other participants' enclaves come from
//! their USER_DATA, which the Cyclone backend reads and the rustdds backend cannot.

use std::time::{Duration, Instant};

use horus_ros_rmw::{Context, DiscoveryEvent};

const DOMAIN: u32 = 42;

#[test]
fn enclaves_are_announced_and_read_where_the_backend_can() {
    let secure = Context::builder()
        .domain_id(DOMAIN)
        .enclave("/secure/arm")
        .build()
        .expect("context with an enclave");
    assert_eq!(secure.enclave(), "/secure/arm");
    let observer = Context::builder()
        .domain_id(DOMAIN)
        .build()
        .expect("observer");
    assert_eq!(observer.enclave(), "/");

    let mut feed = observer.discovery_feed().expect("feed");
    let mut own = None;
    let mut other = None;
    let deadline = Instant::now() + Duration::from_secs(10);
    while own.is_none() || other.is_none() {
        assert!(
            Instant::now() < deadline,
            "participants not reported within 10 s (own {own:?}, other {other:?})"
        );
        if let Some(DiscoveryEvent::ParticipantDiscovered(p)) =
            feed.next_timeout(Duration::from_millis(100))
        {
            if p.gid == observer.gid() {
                own = Some(p.enclave);
            } else if p.gid == secure.gid() {
                other = Some(p.enclave);
            }
        }
    }
    assert_eq!(own, Some(Some("/".to_owned())), "our own enclave");
    let expected = secure
        .capabilities()
        .announces_user_data
        .then(|| "/secure/arm".to_owned());
    assert_eq!(
        other,
        Some(expected),
        "the other participant's enclave on {:?}",
        secure.backend()
    );
}
