//! `wovenform`: parses the command line and runs it; the commands are in `cli/`.

use std::process::ExitCode;

use clap::Parser;

mod cli;

fn main() -> ExitCode {
    // `wovenform … | head`: a closed pipe ends the program quietly, as it ends `ls` or `cat`,
    // instead of a panic on the next line printed (Rust ignores SIGPIPE by default).
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of one signal, before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    quiet_on_failed_output();
    match cli::exec(cli::Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", shortened(&e.message));
            ExitCode::from(e.exit_code)
        }
    }
}

/// The longest error message printed whole, characters: past it (a path of 100 kB quoted
/// back), its head and its tail, where the file and what was expected are said.
const MESSAGE_CHARS: usize = 2000;

fn shortened(message: &str) -> String {
    let count = message.chars().count();
    if count <= MESSAGE_CHARS {
        return message.to_string();
    }
    let head: String = message.chars().take(MESSAGE_CHARS / 2).collect();
    let tail: String = message.chars().skip(count - MESSAGE_CHARS / 4).collect();
    format!(
        "{head} … ({} characters left out) … {tail}",
        count - head.chars().count() - tail.chars().count()
    )
}

/// Standard output that cannot be written (a full disk, `> /dev/full`) ends the program with
/// one line and exit 1, not a panic and its backtrace (`println!` panics on a failed write).
fn quiet_on_failed_output() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let what = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(cause) = what.strip_prefix("failed printing to stdout: ") {
            eprintln!("error: cannot write to standard output: {cause}");
            std::process::exit(1);
        }
        default(info);
    }));
}
