//! `horus-ros completions <shell>`: a completion script generated from the command line's own
//! definition (clap_complete), so it always matches the verbs and flags of this binary.

use clap::CommandFactory;
use clap_complete::Shell;

use crate::CliError;

/// Arguments of `completions`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  horus-ros completions bash > ~/.local/share/bash-completion/completions/horus-ros
  horus-ros completions zsh > \"${fpath[1]}/_horus-ros\"
  horus-ros completions fish > ~/.config/fish/completions/horus-ros.fish")]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// Prints the completion script on stdout.
pub fn run(args: &CompletionsArgs) -> Result<(), CliError> {
    let mut command = crate::Cli::command();
    let name = command.get_name().to_owned();
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut command, name, &mut script);
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_all(&script)
        .and_then(|()| out.flush())
        .map_err(|e| CliError::new(format!("could not write the completion script: {e}")))
}
