//! Where the libraries' log records go in the binary and the tests: standard error, one line
//! each (the device layer's validation messages, which tests also collect and fail on).

/// Prints records of `warn` and above (`LEAKLESS_LOG=info|debug|trace` for more).
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::max_level()
    }

    fn log(&self, record: &log::Record<'_>) {
        // The records say what they are ("validation error: …"): printed as they are.
        if self.enabled(record.metadata()) {
            eprintln!("{}", record.args());
        }
    }

    fn flush(&self) {}
}

static LOG: StderrLog = StderrLog;

/// Sends log records to standard error; a second call (another test) changes nothing.
pub fn install() {
    let level = match std::env::var("LEAKLESS_LOG").as_deref() {
        Ok("info") => log::LevelFilter::Info,
        Ok("debug") => log::LevelFilter::Debug,
        Ok("trace") => log::LevelFilter::Trace,
        _ => log::LevelFilter::Warn,
    };
    if log::set_logger(&LOG).is_ok() {
        log::set_max_level(level);
    }
}
