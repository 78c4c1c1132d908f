//! What a user installs with the command line: shell completions and manual
//! pages, generated from its own definition, so that they never lag it.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args as ClapArgs, CommandFactory};
use clap_complete::Shell;

use crate::Cli;

/// Prints the completion script of a shell on stdout.
///
/// Examples:
///
///   pixgeo completions bash > ~/.local/share/bash-completion/completions/pixgeo
///
///   pixgeo completions zsh > ~/.zfunc/_pixgeo
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct CompletionsArgs {
    /// The shell: bash, elvish, fish, powershell or zsh.
    shell: Shell,
}

/// Writes the manual pages (`pixgeo.1` and one per command, `pixgeo-voronoi.1`
/// and so on) into a folder.
///
/// Example: pixgeo man ~/.local/share/man/man1 && man pixgeo-voronoi
#[derive(ClapArgs)]
#[command(verbatim_doc_comment)]
pub struct ManArgs {
    /// The folder to write the pages into (made if missing).
    dir: PathBuf,
}

pub fn completions(args: CompletionsArgs) -> Result<()> {
    let mut out = Vec::new();
    clap_complete::generate(args.shell, &mut Cli::command(), "pixgeo", &mut out);
    crate::answer(&String::from_utf8_lossy(&out));
    Ok(())
}

pub fn man(args: ManArgs) -> Result<()> {
    std::fs::create_dir_all(&args.dir).with_context(|| format!("making {}", args.dir.display()))?;
    clap_mangen::generate_to(Cli::command(), &args.dir)
        .with_context(|| format!("writing manual pages into {}", args.dir.display()))?;
    note!("wrote the manual pages into {}", args.dir.display());
    Ok(())
}
