//! A person's credentials for a session server: their NATS user and
//! password and the team's CA certificate, read from a file (given with
//! `--credentials FILE`, or named by the environment variable
//! [`CREDENTIALS_ENV`]), never from the command line or the session
//! address. The file is `KEY = VALUE` lines (`#` starts a comment):
//!
//! ```text
//! user = ana
//! password = 6hQ2...
//! ca = team-ca.pem        # relative to this file's folder
//! ```
//!
//! Every key is optional: a file with only `ca` verifies the server of a
//! session without members. With a `ca`, the connection is TLS and the
//! server must present a certificate signed by it.

use std::path::{Path, PathBuf};

/// The environment variable naming a credentials file.
pub const CREDENTIALS_ENV: &str = "SHAPEWRIGHT_SESSION_CREDENTIALS";

/// A user, password and CA certificate. `Debug` hides the password.
#[derive(Clone, Default, PartialEq, Eq)]
pub struct Credentials {
    /// NATS user (also the participant id under it).
    pub user: Option<String>,
    /// Their password.
    pub password: Option<String>,
    /// The team's CA certificate (PEM): TLS, and the server must be
    /// signed by it.
    pub ca: Option<PathBuf>,
}

impl std::fmt::Debug for Credentials {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Credentials")
            .field("user", &self.user)
            .field("password", &self.password.as_ref().map(|_| "<hidden>"))
            .field("ca", &self.ca)
            .finish()
    }
}

/// Why credentials could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CredentialsError {
    /// The file could not be read.
    #[error("cannot read the credentials file {path}: {why}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        why: String,
    },
    /// A line is not `user|password|ca = VALUE`.
    #[error("credentials file {path}, line {line}: {why}")]
    Line {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        why: String,
    },
    /// A password without a user, or a user without a password.
    #[error("credentials file {0}: a user needs a password and a password a user")]
    Half(PathBuf),
    /// The CA certificate named is not there.
    #[error("credentials file {path}: the CA certificate {ca} does not exist")]
    NoCa {
        /// The file.
        path: PathBuf,
        /// The certificate it names.
        ca: PathBuf,
    },
}

impl Credentials {
    /// Reads the credentials file at `path`.
    pub fn read(path: &Path) -> Result<Self, CredentialsError> {
        let text = std::fs::read_to_string(path).map_err(|e| CredentialsError::Read {
            path: path.to_path_buf(),
            why: e.to_string(),
        })?;
        let mut c = Self::default();
        for (i, raw) in text.lines().enumerate() {
            let bad = |why: &str| CredentialsError::Line {
                path: path.to_path_buf(),
                line: i + 1,
                why: why.to_string(),
            };
            let line = match raw.trim() {
                l if l.starts_with('#') => "",
                l => l,
            };
            if line.is_empty() {
                continue;
            }
            let (key, value) = line
                .split_once('=')
                .ok_or_else(|| bad("expected KEY = VALUE"))?;
            let value = value.trim();
            let value = match key.trim() {
                "password" => value,
                // Comments after a value, except in a password.
                _ => value.split(" #").next().unwrap_or("").trim(),
            };
            if value.is_empty() {
                return Err(bad("empty value"));
            }
            match key.trim() {
                "user" => c.user = Some(value.to_string()),
                "password" => c.password = Some(value.to_string()),
                "ca" => {
                    let ca = Path::new(value);
                    let ca = match path.parent() {
                        Some(dir) if ca.is_relative() => dir.join(ca),
                        _ => ca.to_path_buf(),
                    };
                    if !ca.is_file() {
                        return Err(CredentialsError::NoCa {
                            path: path.to_path_buf(),
                            ca,
                        });
                    }
                    c.ca = Some(ca);
                }
                other => {
                    return Err(bad(&format!(
                        "unknown key `{}` (user, password, ca)",
                        other.chars().take(40).collect::<String>()
                    )))
                }
            }
        }
        if c.user.is_some() != c.password.is_some() {
            return Err(CredentialsError::Half(path.to_path_buf()));
        }
        Ok(c)
    }

    /// The credentials file named by [`CREDENTIALS_ENV`], if it is set.
    pub fn from_env() -> Result<Option<Self>, CredentialsError> {
        match std::env::var_os(CREDENTIALS_ENV) {
            Some(p) if !p.is_empty() => Self::read(Path::new(&p)).map(Some),
            _ => Ok(None),
        }
    }

    /// The text of a credentials file (what [`Self::read`] reads back).
    pub fn to_text(&self) -> String {
        let mut out = String::from(
            "# Shapewright session credentials: keep this file to yourself (mode 600).\n",
        );
        if let Some(u) = &self.user {
            out += &format!("user = {u}\n");
        }
        if let Some(p) = &self.password {
            out += &format!("password = {p}\n");
        }
        if let Some(ca) = &self.ca {
            out += &format!("ca = {}\n", ca.display());
        }
        out
    }

    /// Writes [`Self::to_text`] to `path`, readable by its owner only.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        use std::io::Write;
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create(true).truncate(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o600);
        }
        let mut f = options.open(path)?;
        f.write_all(self.to_text().as_bytes())?;
        f.sync_all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_credentials_file_reads_back_and_bad_ones_say_why() {
        let dir = std::env::temp_dir().join(format!("sw-cred-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("ca.pem"), "x").unwrap();
        let c = Credentials {
            user: Some("ana".into()),
            password: Some("p#w =x".into()),
            ca: Some("ca.pem".into()),
        };
        let path = dir.join("ana.cred");
        c.write(&path).unwrap();
        let back = Credentials::read(&path).unwrap();
        assert_eq!(back.user.as_deref(), Some("ana"));
        assert_eq!(back.password.as_deref(), Some("p#w =x"));
        assert_eq!(back.ca, Some(dir.join("ca.pem")));
        assert!(!format!("{back:?}").contains("p#w"));
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            assert_eq!(mode & 0o077, 0, "{mode:o}");
        }
        for (text, want) in [
            ("user = ana\n", "needs a password"),
            ("usr = ana\n", "line 1: unknown key"),
            ("# c\nuser ana\n", "line 2: expected KEY = VALUE"),
            ("ca = nowhere.pem\n", "does not exist"),
            ("user =\n", "empty value"),
        ] {
            std::fs::write(&path, text).unwrap();
            let e = Credentials::read(&path).unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
