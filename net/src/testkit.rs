//! Test support (feature `testkit`): a real `nats-server -js` on
//! 127.0.0.1 with file storage in a temporary directory (Debian's
//! package, installed by scripts/setup.sh), always over TLS with
//! certificates made by scripts/session_certs.sh (one team CA per test
//! process), and a reader that replays a whole stream in one process.

use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use shapewright::doc::shared::{Replica, SharedLog};

use crate::{Credentials, Link, LinkOptions, SessionUrl};

/// This process's certificates (ca.pem, server.pem, server-key.pem), made
/// once by scripts/session_certs.sh for 127.0.0.1 and localhost.
pub fn certs() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("sw-certs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/session_certs.sh");
        let out = Command::new("bash")
            .arg(&script)
            .arg(&dir)
            .args(["127.0.0.1", "localhost"])
            .output()
            .expect("bash runs scripts/session_certs.sh");
        assert!(
            out.status.success(),
            "scripts/session_certs.sh failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        dir
    })
}

/// Link options that verify the test servers' TLS (no user).
pub fn options() -> LinkOptions {
    LinkOptions {
        credentials: Some(Credentials {
            ca: Some(certs().join("ca.pem")),
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// A credentials file naming only the test CA (for a host process:
/// `--credentials FILE` or [`crate::CREDENTIALS_ENV`]).
pub fn credentials_file() -> PathBuf {
    let path = certs().join("ca-only.credentials");
    if !path.exists() {
        let creds = Credentials {
            ca: Some(certs().join("ca.pem")),
            ..Default::default()
        };
        creds.write(&path).expect("the credentials file is written");
    }
    path
}

/// [`options`] as member `user` with `password`.
pub fn member(user: &str, password: &str) -> LinkOptions {
    LinkOptions {
        credentials: Some(Credentials {
            user: Some(user.into()),
            password: Some(password.into()),
            ca: Some(certs().join("ca.pem")),
        }),
        ..Default::default()
    }
}

/// A free TCP port on 127.0.0.1.
pub fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

/// A `nats-server -js` with file storage in a temporary directory.
pub struct Server {
    /// Its client port.
    pub port: u16,
    /// Its storage directory.
    pub dir: PathBuf,
    args: Vec<String>,
    child: Option<Child>,
}

impl Server {
    /// Starts one.
    pub fn start() -> Self {
        Self::with_args(&[])
    }

    /// Started with the configuration `config` (written to a file in its
    /// storage directory), e.g. [`crate::access::server_config`]'s users.
    pub fn with_config(config: &str) -> Self {
        Self::start_with(&[], Some(config))
    }

    /// Started with extra arguments (cluster routes).
    pub fn with_args(extra: &[String]) -> Self {
        Self::start_with(extra, None)
    }

    fn start_with(extra: &[String], config: Option<&str>) -> Self {
        let port = free_port();
        let dir = std::env::temp_dir().join(format!("sw-nats-{}-{port}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let certs = certs();
        let mut args = vec![
            "-a".into(),
            "127.0.0.1".into(),
            "-p".into(),
            port.to_string(),
            "-js".into(),
            "--store_dir".into(),
            dir.to_string_lossy().into_owned(),
            "--tls".into(),
            "--tlscert".into(),
            certs.join("server.pem").to_string_lossy().into_owned(),
            "--tlskey".into(),
            certs.join("server-key.pem").to_string_lossy().into_owned(),
        ];
        if let Some(text) = config {
            let path = dir.join("server.conf");
            std::fs::write(&path, text).unwrap();
            args.extend(["-c".into(), path.to_string_lossy().into_owned()]);
        }
        args.extend(extra.iter().cloned());
        let mut s = Self {
            port,
            dir,
            args,
            child: None,
        };
        s.spawn();
        s
    }

    fn spawn(&mut self) {
        let bin = std::env::var("SHAPEWRIGHT_NATS_SERVER").unwrap_or_else(|_| "nats-server".into());
        let child = Command::new(&bin)
            .args(&self.args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| {
                panic!("cannot start `{bin}` ({e}): run scripts/setup.sh, which installs Debian's nats-server")
            });
        self.child = Some(child);
        wait_for_port(self.port);
    }

    /// The address of document `doc` on it (TLS: join with [`options`]).
    pub fn url(&self, doc: &str) -> SessionUrl {
        SessionUrl::parse(&format!("tls://127.0.0.1:{}/{doc}", self.port)).unwrap()
    }

    /// SIGKILL: no clean shutdown, as a crash or a power cut.
    pub fn kill(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }

    /// Starts again on the same port and storage.
    pub fn restart(&mut self) {
        self.kill();
        self.spawn();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.kill();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A JetStream cluster of `n` servers on loopback (routes between them),
/// each with its own storage.
pub struct Cluster {
    /// The servers.
    pub nodes: Vec<Server>,
}

impl Cluster {
    /// Starts `n` servers that route to each other.
    pub fn start(n: usize) -> Self {
        let routes: Vec<u16> = (0..n).map(|_| free_port()).collect();
        let list = routes
            .iter()
            .map(|p| format!("nats://127.0.0.1:{p}"))
            .collect::<Vec<_>>()
            .join(",");
        let nodes = routes
            .iter()
            .enumerate()
            .map(|(i, p)| {
                Server::with_args(&[
                    "--server_name".into(),
                    format!("sw-n{i}"),
                    "--cluster_name".into(),
                    "sw".into(),
                    "--cluster".into(),
                    format!("nats://127.0.0.1:{p}"),
                    "--routes".into(),
                    list.clone(),
                ])
            })
            .collect();
        Self { nodes }
    }

    /// Document `doc` on the cluster, every server listed.
    pub fn url(&self, doc: &str) -> SessionUrl {
        let servers: Vec<String> = self
            .nodes
            .iter()
            .map(|s| format!("127.0.0.1:{}", s.port))
            .collect();
        SessionUrl::parse(&format!("tls://{}/{doc}", servers.join(","))).expect("a valid url")
    }
}

/// Waits until something listens on `port`.
pub fn wait_for_port(port: u16) {
    let t = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            t.elapsed() < Duration::from_secs(20),
            "nats-server did not start on {port}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The whole stream replayed by one process (an observer that never
/// publishes), with [`options`].
pub fn read_stream(url: &SessionUrl) -> Replica {
    read_stream_with(url, options())
}

/// [`read_stream`] with `options` (a member's credentials).
pub fn read_stream_with(url: &SessionUrl, options: LinkOptions) -> Replica {
    let mut observer = SharedLog::new("observer", "observer", [0.5; 3]).unwrap();
    let mut link = Link::connect(url, "observer", 0, options).unwrap();
    let last = link.last_seq_at_connect();
    let t = Instant::now();
    while observer.confirmed().last_seq() < last {
        // Only read: never publish the observer's join.
        link.receive(&mut observer);
        assert!(t.elapsed() < Duration::from_secs(30), "stream read stalled");
        std::thread::sleep(Duration::from_millis(2));
    }
    observer.confirmed().clone()
}
