//! Checked-in expected outputs (`cli/tests/expected/`): what ros2cli prints, recorded once from
//! the reference and reviewed against ros2cli's source (each test names the source lines that
//! define its format).
//!
//! A transcript file holds one case per command, in the order the test runs them:
//!
//! ```text
//! $ param get /param_node count
//! > Integer value is: 5
//! exit 0
//! ```
//!
//! `> ` lines are stdout, `! ` lines stderr (`>` / `!` alone: an empty line), then the exit code.

use std::path::PathBuf;

use super::Run;

/// `cli/tests/expected/<name>`, read whole.
pub fn expected_file(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/expected")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// One case of a transcript: the command, what it printed and how it ended.
pub fn case(args: &[&str], run: &Run) -> String {
    let command: Vec<String> = args
        .iter()
        .map(|a| {
            if a.is_empty() || a.contains([' ', '"', '\'', '\\']) {
                format!("{a:?}")
            } else {
                (*a).to_owned()
            }
        })
        .collect();
    let mut s = format!("$ {}\n", command.join(" "));
    for (mark, text) in [('>', &run.stdout), ('!', &run.stderr)] {
        let body = text.strip_suffix('\n').unwrap_or(text);
        if !text.is_empty() {
            for line in body.split('\n') {
                if line.is_empty() {
                    s.push(mark);
                } else {
                    s.push_str(&format!("{mark} {line}"));
                }
                s.push('\n');
            }
            if !text.ends_with('\n') {
                s.push_str(&format!("{mark}\\ no newline at end\n"));
            }
        }
    }
    match run.code {
        Some(code) => s.push_str(&format!("exit {code}\n")),
        None => s.push_str("exit none\n"),
    }
    s
}

/// The cases of a transcript file, checked one by one in order.
pub struct Transcript {
    name: String,
    cases: Vec<String>,
    next: usize,
}

impl Transcript {
    /// `cli/tests/expected/<name>`.
    pub fn load(name: &str) -> Self {
        let text = expected_file(name);
        let mut cases: Vec<String> = Vec::new();
        for line in text.split_inclusive('\n') {
            match cases.last_mut() {
                Some(last) if !line.starts_with("$ ") => last.push_str(line),
                _ => cases.push(line.to_owned()),
            }
        }
        Self {
            name: name.to_owned(),
            cases,
            next: 0,
        }
    }

    /// Asserts that `run` of `args` is the transcript's next case.
    pub fn check(&mut self, args: &[&str], run: &Run) {
        let ours = case(args, run);
        let theirs = self.cases.get(self.next).cloned().unwrap_or_default();
        self.next += 1;
        assert_eq!(
            ours, theirs,
            "{} case {} (left: horus-ros, right: expected)",
            self.name, self.next
        );
    }

    /// Asserts that every case was checked.
    pub fn finish(self) {
        assert_eq!(
            self.next,
            self.cases.len(),
            "{}: not every expected case was run",
            self.name
        );
    }
}
