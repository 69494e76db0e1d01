//! The `outlinefit` command line: a thin layer over the library.

mod cli;

fn main() {
    match cli::run() {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            // One line, the whole cause chain.
            let mut msg = format!("{e}");
            let mut src = e.source();
            while let Some(s) = src {
                let s_text = s.to_string();
                if !msg.contains(&s_text) {
                    msg.push_str(": ");
                    msg.push_str(&s_text);
                }
                src = s.source();
            }
            eprintln!("error: {}", msg.replace('\n', " "));
            std::process::exit(1);
        }
    }
}
