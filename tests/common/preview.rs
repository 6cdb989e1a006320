//! A `raydiance preview` started for a test, and its HTTP side read without a browser: plain
//! requests and the event stream, over a socket.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How long a test waits for what the preview should do in well under a second (a debug build
/// on a loaded machine is slow).
pub const PATIENCE: Duration = Duration::from_secs(60);

/// The lab box's scene in `dir` (its include copied beside it) with `body` after the include.
pub fn lab_scene(dir: &Path, body: &str) -> PathBuf {
    let include = std::fs::read_to_string("scenes/lab-box.inc").unwrap();
    std::fs::write(dir.join("lab-box.inc"), include).unwrap();
    let scene = dir.join("scene.scn");
    std::fs::write(&scene, format!("#include \"lab-box.inc\"\n{body}")).unwrap();
    scene
}

/// A small, quick scene of the lab box: `samples` spp at 32x32.
pub fn small_scene(dir: &Path, samples: u32) -> PathBuf {
    lab_scene(
        dir,
        &format!(
            "settings {{ resolution 32, 32  samples {samples}  integrator path  max_depth 4 }}\n\
             object {{ CeilingLight }}\n\
             sphere {{ LeftSphere, 0.3  material {{ Blue }} }}\n"
        ),
    )
}

/// A running preview, ended (by its process id) when dropped.
pub struct Preview {
    child: Child,
    pub address: SocketAddr,
    pub url: String,
}

impl Preview {
    /// Starts `raydiance preview SCENE ARGS...` and reads the address it says it listens on.
    pub fn start(scene: &Path, args: &[&str]) -> Preview {
        match Preview::try_start(scene, args) {
            Ok(preview) => preview,
            Err(stderr) => panic!("raydiance preview did not start:\n{stderr}"),
        }
    }

    /// As `start`; the process's stderr if it ended before saying where it listens.
    pub fn try_start(scene: &Path, args: &[&str]) -> Result<Preview, String> {
        let mut child = Command::new(env!("CARGO_BIN_EXE_raydiance"))
            .arg("preview")
            .arg(scene)
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        let Some(url) = line.split_whitespace().find(|word| word.starts_with("http://")) else {
            let mut stderr = String::new();
            child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
            child.wait().unwrap();
            return Err(format!("{line}{stderr}"));
        };
        let address = url.trim_start_matches("http://").trim_end_matches('/').parse().unwrap();
        Ok(Preview { child, address, url: url.to_string() })
    }

    /// `GET path`: the status and the body.
    pub fn get(&self, path: &str) -> (u16, Vec<u8>) {
        request(self.address, "GET", path)
    }

    pub fn events(&self) -> Events {
        Events::open(self.address)
    }
}

impl Drop for Preview {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `METHOD path` sent as written (no normalisation of `..`): the status and the body.
pub fn request(address: SocketAddr, method: &str, path: &str) -> (u16, Vec<u8>) {
    request_to(address, &address.to_string(), method, path)
}

/// As `request`, naming `host` in the `Host` header.
pub fn request_to(address: SocketAddr, host: &str, method: &str, path: &str) -> (u16, Vec<u8>) {
    let mut stream = TcpStream::connect(address).unwrap();
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    write!(stream, "{method} {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n")
        .unwrap();
    let mut response = Vec::new();
    stream.read_to_end(&mut response).unwrap();
    let end = response.windows(4).position(|w| w == b"\r\n\r\n").expect("a response head");
    let head = String::from_utf8_lossy(&response[..end]);
    let status = head.split_whitespace().nth(1).unwrap().parse().unwrap();
    let mut body = response[end + 4..].to_vec();
    if head.to_ascii_lowercase().contains("transfer-encoding: chunked") {
        body = unchunk(&body);
    }
    (status, body)
}

/// The status of `GET path`, read without waiting for the body (an event stream's never ends).
pub fn status(address: SocketAddr, path: &str) -> u16 {
    let mut stream = TcpStream::connect(address).unwrap();
    stream.set_read_timeout(Some(PATIENCE)).unwrap();
    write!(stream, "GET {path} HTTP/1.1\r\nHost: {address}\r\n\r\n").unwrap();
    let mut line = String::new();
    BufReader::new(stream).read_line(&mut line).unwrap();
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

fn unchunk(mut bytes: &[u8]) -> Vec<u8> {
    let mut body = Vec::new();
    loop {
        let line = bytes.windows(2).position(|w| w == b"\r\n").unwrap();
        let size = usize::from_str_radix(std::str::from_utf8(&bytes[..line]).unwrap().trim(), 16);
        let size = size.unwrap();
        if size == 0 {
            return body;
        }
        body.extend_from_slice(&bytes[line + 2..line + 2 + size]);
        bytes = &bytes[line + 4 + size..];
    }
}

/// One Server-Sent Event.
#[derive(Debug, Clone)]
pub struct Event {
    pub name: String,
    pub data: String,
}

impl Event {
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_str(&self.data).unwrap()
    }
}

/// The preview's event stream.
pub struct Events {
    reader: BufReader<TcpStream>,
}

impl Events {
    pub fn open(address: SocketAddr) -> Events {
        let mut stream = TcpStream::connect(address).unwrap();
        stream.set_read_timeout(Some(PATIENCE)).unwrap();
        write!(stream, "GET /events HTTP/1.1\r\nHost: {address}\r\n\r\n").unwrap();
        let mut reader = BufReader::new(stream);
        let mut line = String::new();
        reader.read_line(&mut line).unwrap();
        assert!(line.starts_with("HTTP/1.1 200"), "{line}");
        while line.trim_end() != "" {
            line.clear();
            reader.read_line(&mut line).unwrap();
            assert!(!line.is_empty(), "the stream ended in its head");
        }
        Events { reader }
    }

    /// The next event (comments skipped).
    pub fn next(&mut self) -> Event {
        let (mut name, mut data) = (String::new(), Vec::new());
        loop {
            let mut line = String::new();
            let read = self.reader.read_line(&mut line).expect("an event within the patience");
            assert!(read > 0, "the event stream ended");
            let line = line.trim_end_matches(['\r', '\n']);
            if line.is_empty() && !data.is_empty() {
                return Event { name, data: data.join("\n") };
            } else if let Some(value) = line.strip_prefix("event: ") {
                name = value.to_string();
            } else if let Some(value) = line.strip_prefix("data: ") {
                data.push(value.to_string());
            }
        }
    }

    /// Reads states until one satisfies `done` (its JSON), with the events seen on the way.
    pub fn until(&mut self, done: impl Fn(&serde_json::Value) -> bool) -> Vec<Event> {
        let start = Instant::now();
        let mut seen = Vec::new();
        loop {
            assert!(start.elapsed() < PATIENCE, "no such state in {PATIENCE:?}: {seen:#?}");
            let event = self.next();
            let finished = event.name == "state" && done(&event.json());
            seen.push(event);
            if finished {
                return seen;
            }
        }
    }
}

/// The samples per pixel of a state's picture, and its render's number.
pub fn picture(state: &serde_json::Value) -> Option<(u64, u64)> {
    let picture = state.get("picture").filter(|p| !p.is_null())?;
    Some((picture["spp"].as_u64().unwrap(), picture["render"].as_u64().unwrap()))
}
