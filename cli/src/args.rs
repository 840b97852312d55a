//! Value parsers for the options that take numbers, so that a bad value is a usage error naming
//! the option and its range (clap prints `invalid value '-1' for '--spin-time <SECONDS>': …`),
//! never a message about an environment variable or a silently clamped value.

use horus_ros_rmw::context::env::DomainId;

/// A number of seconds: finite and not negative (`--spin-time`, `--timeout`).
pub fn seconds(value: &str) -> Result<f64, String> {
    let seconds: f64 = value
        .trim()
        .parse()
        .map_err(|_| "not a number of seconds".to_owned())?;
    if !seconds.is_finite() || seconds < 0.0 {
        return Err("must be a number of seconds from 0 up".to_owned());
    }
    Ok(seconds)
}

/// A DDS domain id, 0 to [`DomainId::MAX`] (`--domain-id`; `ROS_DOMAIN_ID` is checked by the
/// context, with a message naming the variable).
pub fn domain_id(value: &str) -> Result<u32, String> {
    let out_of_range = || format!("must be a domain id from 0 to {}", DomainId::MAX);
    let id: u64 = value.trim().parse().map_err(|_| out_of_range())?;
    u32::try_from(id)
        .ok()
        .filter(|id| DomainId::new(*id).is_ok())
        .ok_or_else(out_of_range)
}

/// ros2topic `positive_int` (`--window`).
pub fn positive_int(value: &str) -> Result<usize, String> {
    match value.trim().parse::<i64>() {
        Ok(v) if v > 0 => usize::try_from(v).map_err(|_| "value must be a positive integer".into()),
        _ => Err("value must be a positive integer".to_owned()),
    }
}

/// ros2topic `positive_float` (`--rate`, `--timeout`, `--keep-alive`, …).
pub fn positive_float(value: &str) -> Result<f64, String> {
    let v: f64 = value
        .trim()
        .parse()
        .map_err(|_| "Expects a floating point number".to_owned())?;
    if v.is_nan() || v <= 0.0 {
        return Err("Value must be positive".to_owned());
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::{domain_id, seconds};

    #[test]
    fn seconds_are_finite_and_not_negative() {
        assert_eq!(seconds("0"), Ok(0.0));
        assert_eq!(seconds("0.5"), Ok(0.5));
        for bad in ["-1", "-0.1", "nan", "inf", "x", ""] {
            assert!(seconds(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn domain_ids_go_from_0_to_232() {
        assert_eq!(domain_id("0"), Ok(0));
        assert_eq!(domain_id("232"), Ok(232));
        for bad in ["233", "300", "-1", "4294967296", "x"] {
            assert_eq!(
                domain_id(bad),
                Err("must be a domain id from 0 to 232".to_owned()),
                "{bad}"
            );
        }
    }
}
