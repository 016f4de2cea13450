//! The `framedyn` command: see the `framedyn_cli` library for the commands,
//! scene files and exit codes.

use std::process::ExitCode;

fn main() -> ExitCode {
    let code = framedyn_cli::main_with_args(std::env::args_os());
    ExitCode::from(u8::try_from(code).unwrap_or(1))
}
