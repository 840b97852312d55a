//! Unit helpers: `100_u64.hz()`, `500_u64.ms()`, `200_u64.us()`.

use std::time::Duration;

/// A frequency in hertz (ticks per second).
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Frequency(f64);

impl Frequency {
    /// `hz` ticks per second.
    pub fn from_hz(hz: f64) -> Self {
        Self(hz)
    }

    /// Ticks per second.
    pub fn hz(self) -> f64 {
        self.0
    }

    /// Whether it is positive and finite (a usable rate).
    pub fn is_valid(self) -> bool {
        self.0.is_finite() && self.0 > 0.0
    }

    /// The period (`1 / hz`); `None` if the frequency is not [valid](Self::is_valid).
    pub fn period(self) -> Option<Duration> {
        if self.is_valid() {
            Duration::try_from_secs_f64(1.0 / self.0).ok()
        } else {
            None
        }
    }
}

/// `.hz()`, `.ms()`, `.us()`, `.ns()`, `.secs()` on integers and floats.
pub trait Units {
    /// This many hertz.
    fn hz(self) -> Frequency;
    /// This many milliseconds.
    fn ms(self) -> Duration;
    /// This many microseconds.
    fn us(self) -> Duration;
    /// This many nanoseconds.
    fn ns(self) -> Duration;
    /// This many seconds.
    fn secs(self) -> Duration;
}

macro_rules! integer_units {
    ($($t:ty),*) => {$(
        impl Units for $t {
            fn hz(self) -> Frequency {
                Frequency(self as f64)
            }
            fn ms(self) -> Duration {
                Duration::from_millis(self as u64)
            }
            fn us(self) -> Duration {
                Duration::from_micros(self as u64)
            }
            fn ns(self) -> Duration {
                Duration::from_nanos(self as u64)
            }
            fn secs(self) -> Duration {
                Duration::from_secs(self as u64)
            }
        }
    )*};
}

integer_units!(u8, u16, u32, u64, usize);

impl Units for f64 {
    fn hz(self) -> Frequency {
        Frequency(self)
    }
    fn ms(self) -> Duration {
        Duration::try_from_secs_f64(self / 1e3).unwrap_or_default()
    }
    fn us(self) -> Duration {
        Duration::try_from_secs_f64(self / 1e6).unwrap_or_default()
    }
    fn ns(self) -> Duration {
        Duration::try_from_secs_f64(self / 1e9).unwrap_or_default()
    }
    fn secs(self) -> Duration {
        Duration::try_from_secs_f64(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_what_they_say() {
        assert_eq!(100_u64.hz().period(), Some(Duration::from_millis(10)));
        assert_eq!(500_u64.ms(), Duration::from_millis(500));
        assert_eq!(200_u64.us(), Duration::from_micros(200));
        assert_eq!(3_u32.secs(), Duration::from_secs(3));
        assert_eq!(0_u64.hz().period(), None);
        assert_eq!(f64::NAN.hz().period(), None);
        assert_eq!(1.5_f64.ms(), Duration::from_micros(1500));
    }
}
