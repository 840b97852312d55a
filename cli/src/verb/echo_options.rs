//! The output options `topic echo` and `service echo` share (ros2topic 0.32.2 `verb/echo.py`
//! and ros2service 0.32.2 `verb/echo.py` define them alike): how messages are converted for
//! printing.

use crate::dynamic::convert::ConvertOptions;

/// ros2cli echo's `DEFAULT_TRUNCATE_LENGTH`.
const DEFAULT_TRUNCATE_LENGTH: usize = 128;

/// `--full-length`, `--truncate-length`, `--no-arr`, `--no-str`, `--flow-style`.
#[derive(Debug, Clone, clap::Args)]
pub struct EchoOptions {
    /// Output all elements for arrays, bytes, and string with a length > '--truncate-length', by
    /// default they are truncated after '--truncate-length' elements with '...''
    #[arg(short = 'f', long)]
    pub full_length: bool,
    /// The length to truncate arrays, bytes, and string to (default: 128)
    #[arg(short = 'l', long, default_value_t = DEFAULT_TRUNCATE_LENGTH)]
    pub truncate_length: usize,
    /// Don't print array fields of messages
    #[arg(long)]
    pub no_arr: bool,
    /// Don't print string fields of messages
    #[arg(long)]
    pub no_str: bool,
    /// Print collections in the block style (not available with csv format)
    #[arg(long)]
    pub flow_style: bool,
}

impl EchoOptions {
    /// The conversion options (`message_to_yaml` / `message_to_csv` arguments).
    pub fn convert(&self) -> ConvertOptions {
        ConvertOptions {
            truncate_length: (!self.full_length).then_some(self.truncate_length),
            no_arr: self.no_arr,
            no_str: self.no_str,
        }
    }
}
