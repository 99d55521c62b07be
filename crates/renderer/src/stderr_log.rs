//! Where the libraries' log records go in the binary and the tests: standard error, one line
//! each, as the records say them ("validation error: …"). Records of `warn` and above by
//! default; `LEAKLESS_LOG` takes env_logger's filters (`info`, `leakless_device=debug`, …).

use std::io::Write;

/// Sends log records to standard error; a second call (another test) changes nothing.
pub fn install() {
    let env = env_logger::Env::new().filter_or("LEAKLESS_LOG", "warn");
    let _ = env_logger::Builder::from_env(env).format(|out, record| writeln!(out, "{}", record.args())).try_init();
}
