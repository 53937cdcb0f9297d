//! Running CalculiX: find `ccx` on the `PATH`, run a deck in a fresh temporary directory
//! under a time limit, and hand back its `.dat` output.

use crate::cancel::CancelToken;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// The Debian/Ubuntu command that installs CalculiX's solver.
pub const INSTALL_HINT: &str = "apt-get install calculix-ccx";

/// The job name of every run (the files are `job.inp`, `job.dat`, ...).
const JOB: &str = "job";

/// Why a CalculiX run gave no output to read.
#[derive(Debug, thiserror::Error)]
pub enum CcxError {
    /// No `ccx` on the `PATH`.
    #[error("CalculiX (`ccx`) is not installed or not on the PATH: install it with `{INSTALL_HINT}` (Debian/Ubuntu)")]
    NotInstalled,
    /// The temporary directory or its files could not be made or read.
    #[error("{what} {}: {error}", path.display())]
    Io {
        /// What was being done.
        what: &'static str,
        /// Where.
        path: PathBuf,
        /// The OS error.
        error: std::io::Error,
    },
    /// `ccx` ran past the time limit and was stopped.
    #[error("ccx ran longer than {seconds} s and was stopped (a finer mesh or more load steps take longer; raise --timeout)")]
    Timeout {
        /// The limit.
        seconds: u64,
    },
    /// The run was cancelled, and `ccx` stopped.
    #[error("cancelled")]
    Cancelled,
    /// `ccx` reported an error or exited with a failure status.
    #[error("ccx failed (exit status {status}): {message}")]
    Failed {
        /// Its exit status (`none` when killed by a signal).
        status: String,
        /// Its `*ERROR` line, or the end of its output.
        message: String,
    },
}

/// A failed run: why, and the `.dat` text it had written by then (empty if none).
#[derive(Debug)]
pub struct CcxFailure {
    /// Why it failed.
    pub error: CcxError,
    /// Its `.dat` output up to the failure.
    pub dat: String,
}

/// A CalculiX solver executable.
#[derive(Debug, Clone)]
pub struct Ccx {
    /// The executable.
    pub program: PathBuf,
    /// A run stops ([`CcxError::Cancelled`], `ccx` killed) soon after this is cancelled.
    cancel: CancelToken,
}

/// What one run printed and wrote.
#[derive(Debug, Clone)]
pub struct CcxOutput {
    /// The `.dat` file's text.
    pub dat: String,
    /// What `ccx` printed (its log), for messages.
    pub log: String,
    /// Wall-clock seconds.
    pub seconds: f64,
}

impl Ccx {
    /// `ccx` from the `PATH`, if it is there.
    pub fn find() -> Result<Ccx, CcxError> {
        let path = std::env::var_os("PATH").ok_or(CcxError::NotInstalled)?;
        std::env::split_paths(&path)
            .map(|dir| dir.join("ccx"))
            .find(|p| is_executable(p))
            .map(|program| Ccx {
                program,
                cancel: CancelToken::new(),
            })
            .ok_or(CcxError::NotInstalled)
    }

    /// This executable, its runs stopped ([`CcxError::Cancelled`]) within a poll (20 ms)
    /// of `cancel` being cancelled.
    pub fn with_cancel(mut self, cancel: &CancelToken) -> Ccx {
        self.cancel = cancel.clone();
        self
    }

    /// Runs `deck` in a new temporary directory (removed afterwards), stopping `ccx` after
    /// `timeout`. A run that prints `*ERROR` or exits with a failure status is an error
    /// carrying CalculiX's own message.
    pub fn run(&self, deck: &str, timeout: Duration) -> Result<CcxOutput, CcxError> {
        self.run_partial(deck, timeout).map_err(|f| f.error)
    }

    /// [`Ccx::run`], keeping what a failed run had written to its `.dat` file by then (the
    /// steps that converged before it stopped).
    pub fn run_partial(&self, deck: &str, timeout: Duration) -> Result<CcxOutput, CcxFailure> {
        let dir = scratch_dir().map_err(|error| CcxFailure {
            error,
            dat: String::new(),
        })?;
        let result = self
            .run_in(&dir, deck, timeout)
            .map_err(|error| CcxFailure {
                error,
                dat: fs::read_to_string(dir.join(format!("{JOB}.dat"))).unwrap_or_default(),
            });
        let _ = fs::remove_dir_all(&dir);
        result
    }

    fn run_in(&self, dir: &Path, deck: &str, timeout: Duration) -> Result<CcxOutput, CcxError> {
        let io = |what, path: PathBuf| move |error| CcxError::Io { what, path, error };
        let input = dir.join(format!("{JOB}.inp"));
        fs::write(&input, deck).map_err(io("cannot write the deck", input.clone()))?;
        let log_path = dir.join(format!("{JOB}.log"));
        let log_file =
            fs::File::create(&log_path).map_err(io("cannot create", log_path.clone()))?;
        let err_file = log_file
            .try_clone()
            .map_err(io("cannot create", log_path.clone()))?;
        let mut command = Command::new(&self.program);
        command
            .args(["-i", JOB])
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(log_file)
            .stderr(err_file);
        // One thread: the machine is usually busy with other work, and these models are small.
        if std::env::var_os("OMP_NUM_THREADS").is_none() {
            command.env("OMP_NUM_THREADS", "1");
        }
        let t0 = Instant::now();
        let mut child = command
            .spawn()
            .map_err(io("cannot run", self.program.clone()))?;
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if self.cancel.is_cancelled() => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(CcxError::Cancelled);
                }
                Ok(None) if t0.elapsed() > timeout => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(CcxError::Timeout {
                        seconds: timeout.as_secs(),
                    });
                }
                Ok(None) => std::thread::sleep(Duration::from_millis(20)),
                Err(e) => return Err(io("cannot wait for", self.program.clone())(e)),
            }
        };
        let seconds = t0.elapsed().as_secs_f64();
        let log = fs::read_to_string(&log_path).unwrap_or_default();
        let error_line = log
            .lines()
            .map(str::trim)
            .find(|l| l.starts_with("*ERROR"))
            .map(str::to_string);
        if !status.success() || error_line.is_some() {
            let message = error_line.unwrap_or_else(|| {
                let tail: Vec<&str> = log
                    .lines()
                    .rev()
                    .filter(|l| !l.trim().is_empty())
                    .take(3)
                    .collect();
                tail.into_iter()
                    .rev()
                    .map(str::trim)
                    .collect::<Vec<_>>()
                    .join(" / ")
            });
            return Err(CcxError::Failed {
                status: status
                    .code()
                    .map_or_else(|| "none".to_string(), |c| c.to_string()),
                message,
            });
        }
        let dat_path = dir.join(format!("{JOB}.dat"));
        let dat =
            fs::read_to_string(&dat_path).map_err(io("cannot read ccx's output", dat_path))?;
        Ok(CcxOutput { dat, log, seconds })
    }
}

fn is_executable(p: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    }
    #[cfg(not(unix))]
    {
        p.is_file()
    }
}

/// A new, empty, private directory under the system's temporary directory.
fn scratch_dir() -> Result<PathBuf, CcxError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    let dir = std::env::temp_dir().join(format!(
        "prbfit-ccx-{}-{}-{nanos}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    fs::create_dir(&dir).map_err(|error| CcxError::Io {
        what: "cannot create the work directory",
        path: dir.clone(),
        error,
    })?;
    Ok(dir)
}
