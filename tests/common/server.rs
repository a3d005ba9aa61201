//! A `vk-render serve` of the tests' own, on a free loopback port, spoken to over plain TCP: a small HTTP/1.1
//! client that sends exactly the bytes a test means (hostile ones included) and reads whole answers.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// One server at a time: each test's own, so that two do not share the two cores.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// A running server, stopped (SIGTERM, then SIGKILL) when dropped.
pub struct Server {
    pub child: Child,
    pub address: SocketAddr,
    /// What it prints after its address (the sign-in link), line by line.
    printed: Mutex<std::sync::mpsc::Receiver<String>>,
    /// Its standard error so far (read on a thread of its own, so that the server never blocks on it).
    stderr: Arc<Mutex<String>>,
    /// That thread, which ends when the server's standard error closes (it has exited).
    stderr_reader: Option<std::thread::JoinHandle<()>>,
    _turn: MutexGuard<'static, ()>,
}

/// An answer.
#[derive(Debug)]
pub struct Answer {
    pub status: u16,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Answer {
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, v)| v.as_str())
    }

    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }

    pub fn json(&self) -> serde_json::Value {
        serde_json::from_slice(&self.body).unwrap_or_else(|e| panic!("not JSON ({e}): {}", self.text()))
    }
}

impl Server {
    /// `vk-render --validate serve --listen LISTEN ARGS`, with `environment` set, once it prints its address.
    pub fn start(listen: &str, args: &[&str], environment: &[(&str, &str)]) -> Self {
        Self::spawn(&["--validate"], listen, args, environment)
    }

    /// `vk-render GLOBAL serve --listen LISTEN ARGS` (the benchmark's, without the validation layer).
    pub fn spawn(global: &[&str], listen: &str, args: &[&str], environment: &[(&str, &str)]) -> Self {
        let turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
        let mut command = Command::new(env!("CARGO_BIN_EXE_vk-render"));
        command.args(global).args(["serve", "--listen", listen]).args(args);
        command.env_remove("VK_RENDER_TOKEN");
        for (key, value) in environment {
            command.env(key, value);
        }
        let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("start vk-render serve");
        let stdout = child.stdout.take().expect("its standard output");
        let (stderr, stderr_reader) = kept_on_a_thread(child.stderr.take().expect("its standard error"));
        let (lines, printed) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            use std::io::BufRead;
            for line in std::io::BufReader::new(stdout).lines().map_while(Result::ok) {
                if lines.send(line).is_err() {
                    break;
                }
            }
        });
        let first: String = match printed.recv_timeout(Duration::from_secs(120)) {
            Ok(line) => line,
            Err(_) => {
                let _ = child.kill();
                let _ = child.wait();
                // Its standard error is whole once the reading thread has seen the pipe close.
                let _ = stderr_reader.join();
                panic!("vk-render serve did not start: {}", stderr.lock().unwrap_or_else(|p| p.into_inner()));
            }
        };
        let address = first
            .strip_prefix("listening on http://")
            .unwrap_or_else(|| panic!("its first line: {first}"))
            .parse()
            .expect("an address");
        Self { child, address, printed: Mutex::new(printed), stderr, stderr_reader: Some(stderr_reader), _turn: turn }
    }

    /// A server of the tests' defaults on 127.0.0.1.
    pub fn local() -> Self {
        Self::start("127.0.0.1:0", &["--workers", "1"], &[])
    }

    /// The loopback address of its port (a server on 0.0.0.0 is reached there too).
    pub fn loopback(&self) -> SocketAddr {
        SocketAddr::from(([127, 0, 0, 1], self.address.port()))
    }

    /// Sends `request` (the whole request's bytes) and reads the answer.
    pub fn raw(&self, request: &[u8]) -> Answer {
        raw(self.loopback(), request)
    }

    /// `METHOD PATH` with `headers` and `body`.
    pub fn send(&self, method: &str, path: &str, headers: &[(&str, &str)], body: &[u8]) -> Answer {
        request(self.loopback(), method, path, headers, body)
    }

    pub fn get(&self, path: &str) -> Answer {
        self.send("GET", path, &[], b"")
    }

    pub fn post_json(&self, path: &str, body: &serde_json::Value) -> Answer {
        self.send("POST", path, &[("Content-Type", "application/json")], body.to_string().as_bytes())
    }

    /// A multipart form of `parts` (name, file name, bytes) to `path`.
    pub fn post_form(&self, path: &str, parts: &[(&str, Option<&str>, &[u8])]) -> Answer {
        let (kind, body) = multipart(parts);
        self.send("POST", path, &[("Content-Type", &kind)], &body)
    }

    /// The server's peak resident size so far, in MB.
    pub fn peak_mb(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap_or_default();
        let kb: u64 = status
            .lines()
            .find(|l| l.starts_with("VmHWM:"))
            .and_then(|l| l.split_whitespace().nth(1)?.parse().ok())
            .unwrap_or(0);
        kb / 1024
    }

    /// SIGTERM, then its exit status and standard error (SIGKILL after `within`).
    pub fn terminate(self, within: Duration) -> (Option<i32>, String, Duration) {
        self.signal_stop();
        self.exit_status(within)
    }

    /// Sends SIGTERM.
    /// The next line it prints after its address, within `within`.
    pub fn next_printed_line(&self, within: Duration) -> String {
        let lines = self.printed.lock().unwrap_or_else(|p| p.into_inner());
        lines.recv_timeout(within).unwrap_or_else(|_| panic!("no further line printed within {within:?}"))
    }

    /// Polls `condition` every 20 ms until it holds, failing the test naming `what` after `within`.
    pub fn wait_for(&self, what: &str, within: Duration, condition: impl Fn(&Self) -> bool) {
        let started = Instant::now();
        while !condition(self) {
            assert!(started.elapsed() < within, "not within {within:?}: {what}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    pub fn signal_stop(&self) {
        // SAFETY: kill(2) on our own child's pid.
        unsafe {
            libc::kill(self.child.id() as i32, libc::SIGTERM);
        }
    }

    /// Waits for the server to exit: its status, standard error and how long it took (SIGKILL after
    /// `within`).
    pub fn exit_status(mut self, within: Duration) -> (Option<i32>, String, Duration) {
        let started = Instant::now();
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("wait") {
                break status.code();
            }
            if started.elapsed() > within {
                let _ = self.child.kill();
                break None;
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        // The reading thread ends when the pipe closes, once the server has exited (and any child of its).
        if status.is_some() {
            if let Some(reader) = self.stderr_reader.take() {
                let _ = reader.join();
            }
        }
        let stderr = self.stderr.lock().unwrap_or_else(|p| p.into_inner()).clone();
        (status, stderr, started.elapsed())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Sends `request` (the whole request's bytes) to `address` and reads the answer.
pub fn raw(address: SocketAddr, request: &[u8]) -> Answer {
    let mut stream = TcpStream::connect(address).expect("connect");
    stream.set_read_timeout(Some(Duration::from_secs(180))).expect("a read timeout");
    stream.write_all(request).expect("send the request");
    read_answer(&mut stream)
}

/// What a child writes to `pipe`, kept as it comes, read on a thread of its own (so that the child never
/// blocks on it), which ends when the pipe closes.
pub fn kept_on_a_thread(mut pipe: impl Read + Send + 'static) -> (Arc<Mutex<String>>, std::thread::JoinHandle<()>) {
    let text = Arc::new(Mutex::new(String::new()));
    let kept = text.clone();
    let reader = std::thread::spawn(move || {
        let mut buffer = [0u8; 4096];
        while let Ok(n) = pipe.read(&mut buffer) {
            if n == 0 {
                break;
            }
            kept.lock().unwrap_or_else(|p| p.into_inner()).push_str(&String::from_utf8_lossy(&buffer[..n]));
        }
    });
    (text, reader)
}

/// `METHOD PATH` with `headers` and `body` to `address`, on a connection of its own.
pub fn request(address: SocketAddr, method: &str, path: &str, headers: &[(&str, &str)], body: &[u8]) -> Answer {
    let mut request = format!("{method} {path} HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n");
    for (name, value) in headers {
        request.push_str(&format!("{name}: {value}\r\n"));
    }
    request.push_str(&format!("Content-Length: {}\r\n\r\n", body.len()));
    let mut bytes = request.into_bytes();
    bytes.extend_from_slice(body);
    raw(address, &bytes)
}

/// Reads an HTTP/1.1 answer: status, headers, and the body its Content-Length gives (else to the end of the
/// connection; de-chunked).
pub fn read_answer(stream: &mut impl Read) -> Answer {
    let mut bytes = Vec::new();
    let mut buffer = [0u8; 64 << 10];
    let end = loop {
        if let Some(end) = bytes.windows(4).position(|w| w == b"\r\n\r\n") {
            break end;
        }
        match stream.read(&mut buffer) {
            Ok(0) | Err(_) => {
                panic!("no answer's head in {} bytes: {:?}", bytes.len(), String::from_utf8_lossy(&bytes))
            }
            Ok(n) => bytes.extend_from_slice(&buffer[..n]),
        }
    };
    let head = String::from_utf8_lossy(&bytes[..end]).into_owned();
    let mut lines = head.split("\r\n");
    let status = lines.next().and_then(|l| l.split(' ').nth(1)).and_then(|s| s.parse().ok()).expect("a status");
    let headers: Vec<(String, String)> =
        lines.filter_map(|l| l.split_once(':')).map(|(n, v)| (n.trim().to_string(), v.trim().to_string())).collect();
    let mut body = bytes[end + 4..].to_vec();
    let length = headers
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case("content-length"))
        .and_then(|(_, v)| v.parse::<usize>().ok());
    match length {
        Some(length) => {
            while body.len() < length {
                match stream.read(&mut buffer) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => body.extend_from_slice(&buffer[..n]),
                }
            }
        }
        None => {
            let _ = stream.read_to_end(&mut body);
        }
    }
    let chunked = headers.iter().any(|(n, v)| n.eq_ignore_ascii_case("transfer-encoding") && v.contains("chunked"));
    if chunked {
        body = dechunked(&body);
    }
    Answer { status, headers, body }
}

fn dechunked(mut body: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let Some(line_end) = body.windows(2).position(|w| w == b"\r\n") else { return out };
        let size = usize::from_str_radix(String::from_utf8_lossy(&body[..line_end]).trim(), 16).unwrap_or(0);
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&body[line_end + 2..line_end + 2 + size]);
        body = &body[line_end + 2 + size + 2..];
    }
}

/// A multipart/form-data body of `parts`, and its Content-Type.
pub fn multipart(parts: &[(&str, Option<&str>, &[u8])]) -> (String, Vec<u8>) {
    let boundary = "vk-render-test-boundary-7f3a";
    let mut body = Vec::new();
    for (name, file, bytes) in parts {
        body.extend_from_slice(format!("--{boundary}\r\n").as_bytes());
        match file {
            Some(file) => body.extend_from_slice(
                format!(
                    "Content-Disposition: form-data; name=\"{name}\"; filename=\"{file}\"\r\nContent-Type: application/octet-stream\r\n\r\n"
                )
                .as_bytes(),
            ),
            None => body.extend_from_slice(format!("Content-Disposition: form-data; name=\"{name}\"\r\n\r\n").as_bytes()),
        }
        body.extend_from_slice(bytes);
        body.extend_from_slice(b"\r\n");
    }
    body.extend_from_slice(format!("--{boundary}--\r\n").as_bytes());
    (format!("multipart/form-data; boundary={boundary}"), body)
}
