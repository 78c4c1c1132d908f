//! The `pixgeo` command: the command-line library run on this process's
//! arguments.

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    let status = pixgeo_cli::main_with(std::env::args_os());
    std::process::ExitCode::from(u8::try_from(status).unwrap_or(1))
}
