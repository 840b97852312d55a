//! The services guide's `GetMapRegion` service: a map server that validates its requests, and a
//! client using each way of calling it.
//!
//! ```text
//! cargo run -p horus-ros-nodes --example get_map_region
//! ```
//!
//! - the server rejects a non-positive resolution and inverted bounds with the guide's messages;
//! - `call` with a valid request gets the map; with an invalid one it gets
//!   `ServiceError::ServiceFailed` with the server's message, at once (no timeout);
//! - `call_resilient` / `call_resilient_with` retry only Timeout and Transport errors;
//! - `call_optional` on a service nobody serves returns `Ok(None)` (after its timeout).
//!
//! Server and clients run in one process (on the default node) but talk over DDS, so the map
//! travels as a real, fragmented DDS sample (200 x 200 cells = 40 kB).

use std::time::Instant;

use horus::prelude::*;

service! {
    GetMapRegion {
        request {
            x_min: f64,
            y_min: f64,
            x_max: f64,
            y_max: f64,
            resolution: f64,
        }
        response {
            width: u32,
            height: u32,
            data: Vec<u8>,
            timestamp: u64,
        }
    }
}

/// An occupancy grid: row-major cells, 0 free, 100 occupied (as in `nav_msgs/OccupancyGrid`).
struct Map {
    width: u32,
    height: u32,
    data: Vec<u8>,
}

/// A made-up world for the map server: walls along x = 0 and y = 0 and a round pillar of
/// radius 1 m at (5, 5); each cell is sampled at its centre.
fn generate_map(x_min: f64, y_min: f64, x_max: f64, y_max: f64, resolution: f64) -> Map {
    let cells = |extent: f64| (extent / resolution).ceil() as u32;
    let (width, height) = (cells(x_max - x_min), cells(y_max - y_min));
    let mut data = Vec::with_capacity(width as usize * height as usize);
    for row in 0..height {
        let y = y_min + (f64::from(row) + 0.5) * resolution;
        for col in 0..width {
            let x = x_min + (f64::from(col) + 0.5) * resolution;
            let wall = x.abs() < resolution || y.abs() < resolution;
            let pillar = (x - 5.0).hypot(y - 5.0) <= 1.0;
            data.push(if wall || pillar { 100 } else { 0 });
        }
    }
    Map {
        width,
        height,
        data,
    }
}

fn main() -> Result<()> {
    // ---- Service server (the guide's, with its validation) ------------------------------------
    let server = ServiceServerBuilder::<GetMapRegion>::new()
        .on_request(|req| {
            if req.resolution <= 0.0 {
                return Err("Resolution must be positive".into());
            }
            if req.x_max <= req.x_min || req.y_max <= req.y_min {
                return Err("Invalid region bounds".into());
            }

            let map = generate_map(req.x_min, req.y_min, req.x_max, req.y_max, req.resolution);
            Ok(GetMapRegionResponse {
                width: map.width,
                height: map.height,
                data: map.data,
                timestamp: horus::timestamp_now(),
            })
        })
        .poll_interval(Duration::from_millis(1)) // the longest the server sleeps between checks (default: 5ms)
        .build()?;
    println!("Map server on {}", server.name().as_str());

    // ---- Blocking client ----------------------------------------------------------------------
    // Wakes at least every 500 µs while waiting (replies wake it at once anyway).
    let mut client = ServiceClient::<GetMapRegion>::with_poll_interval(Duration::from_micros(500))?;

    let request = GetMapRegionRequest {
        x_min: 0.0,
        y_min: 0.0,
        x_max: 10.0,
        y_max: 10.0,
        resolution: 0.05,
    };
    let started = Instant::now();
    let response = client.call(request.clone(), Duration::from_secs(1))?;
    let occupied = response.data.iter().filter(|&&cell| cell == 100).count();
    println!(
        "Map: {}x{} pixels ({} bytes, {occupied} occupied) in {:.1?}, stamped {}",
        response.width,
        response.height,
        response.data.len(),
        started.elapsed(),
        response.timestamp
    );

    // ---- Error handling: an invalid request ---------------------------------------------------
    let invalid = GetMapRegionRequest {
        resolution: 0.0,
        ..request.clone()
    };
    let started = Instant::now();
    match client.call(invalid, Duration::from_secs(1)) {
        Ok(response) => println!("unexpected map {}x{}", response.width, response.height),
        Err(ServiceError::Timeout) => println!("server didn't respond in time"),
        Err(ServiceError::ServiceFailed(msg)) => {
            println!("ServiceFailed after {:.1?}: {msg}", started.elapsed())
        }
        Err(ServiceError::NoServer) => println!("no server found"),
        Err(ServiceError::Transport(msg)) => println!("transport error: {msg}"),
    }
    let inverted = GetMapRegionRequest {
        x_min: 10.0,
        x_max: 0.0,
        ..request.clone()
    };
    if let Err(e) = client.call(inverted, Duration::from_secs(1)) {
        println!("inverted bounds: {e}");
    }

    // ---- Resilient calls (auto-retry on Timeout and Transport) --------------------------------
    // Default: 3 retries, exponential backoff from 10 ms.
    let small = GetMapRegionRequest {
        x_min: 4.0,
        y_min: 4.0,
        x_max: 6.0,
        y_max: 6.0,
        resolution: 0.5,
    };
    let response = client.call_resilient(small.clone(), Duration::from_secs(5))?;
    println!(
        "call_resilient: {}x{} around the pillar: {:?}",
        response.width, response.height, response.data
    );
    // Custom policy: 5 retries, 20 ms initial backoff.
    let response = client.call_resilient_with(
        small,
        Duration::from_secs(5),
        RetryConfig::new(5, Duration::from_millis(20)),
    )?;
    println!(
        "call_resilient_with: {}x{}",
        response.width, response.height
    );
    // ServiceFailed is permanent: not retried, returned at once.
    let started = Instant::now();
    let result = client.call_resilient(
        GetMapRegionRequest {
            resolution: -1.0,
            ..request.clone()
        },
        Duration::from_secs(5),
    );
    println!(
        "call_resilient, invalid request: {:?} after {:.1?} (failures so far: {})",
        result.map(|r| r.width),
        started.elapsed(),
        server.failed_count()
    );

    // ---- Optional response: a service nobody serves --------------------------------------------
    let mut nobody = ServiceClient::<GetMapRegion>::builder()
        .name("/archived_map")
        .build()?;
    match nobody.call_optional(request, Duration::from_millis(100))? {
        Some(response) => println!("Map: {}x{}", response.width, response.height),
        None => println!("/archived_map: No server available"),
    }

    // ---- Stopping the server -------------------------------------------------------------------
    println!(
        "served {} requests, {} failed",
        server.served_count(),
        server.failed_count()
    );
    server.stop(); // or just drop it
    Ok(())
}
