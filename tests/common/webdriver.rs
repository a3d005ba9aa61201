//! A headless Chromium driven over WebDriver (Debian's `chromium` and its matching `chromium-driver`): the
//! few commands the browser tests use, spoken as JSON over the tests' own HTTP client.

use std::net::{SocketAddr, TcpListener, TcpStream};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::server::read_answer;

/// A chromedriver and one browser session, both ended when dropped.
pub struct Browser {
    driver: Child,
    address: SocketAddr,
    session: String,
}

/// Where Debian installs them.
pub const CHROMIUM: &str = "/usr/bin/chromium";
pub const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

impl Browser {
    /// Starts chromedriver on a free port and a headless browser of `width` x `height` CSS pixels at a
    /// device scale of 1 (a canvas's pixels are the page's), keeping the console's messages. Its WebGL2 is
    /// SwiftShader's (the CPU), asked for by name: Chromium is removing its automatic fallback to it.
    pub fn start(width: u32, height: u32) -> Self {
        Self::start_with(width, height, &["--use-angle=swiftshader", "--enable-unsafe-swiftshader"])
    }

    /// A browser as [`Browser::start`]'s with `flags` instead of the WebGL ones (`--disable-webgl`: none).
    pub fn start_with(width: u32, height: u32, flags: &[&str]) -> Self {
        let port = TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).expect("a free port").port();
        let driver = Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromedriver (make setup-test installs chromium-driver)");
        let address = SocketAddr::from(([127, 0, 0, 1], port));
        let started = Instant::now();
        while TcpStream::connect(address).is_err() {
            assert!(started.elapsed() < Duration::from_secs(30), "chromedriver did not start");
            std::thread::sleep(Duration::from_millis(50));
        }
        let mut browser = Self { driver, address, session: String::new() };
        let mut args: Vec<String> = [
            "--headless=new",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--force-device-scale-factor=1",
            "--force-color-profile=srgb",
            "--no-first-run",
            "--disable-extensions",
            "--disable-background-networking",
            "--disable-component-update",
        ]
        .into_iter()
        .map(String::from)
        .collect();
        args.push(format!("--window-size={width},{height}"));
        args.extend(flags.iter().map(|f| f.to_string()));
        let capabilities = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {
                "binary": CHROMIUM,
                "args": args,
            },
            "goog:loggingPrefs": {"browser": "ALL"},
            // No limit on a script's run (WebDriver's default is 30 s): on a loaded machine the page's
            // thread may be drawing with SwiftShader for longer before it runs the script, which is not a
            // failure. Each wait says its own deadline (`wait_for`), and a reply never sent is the socket's.
            "timeouts": {"script": null},
        }}});
        let created = browser.call("POST", "/session", &capabilities);
        browser.session = created["sessionId"].as_str().expect("a session id").to_string();
        browser
    }

    /// A WebDriver command; its `value`. A WebDriver error fails the test.
    pub fn call(&self, method: &str, path: &str, body: &Value) -> Value {
        let mut stream = TcpStream::connect(self.address).expect("connect to chromedriver");
        // A hang's deadline, not a page's: a script waits for the page's thread, which a busy machine may
        // keep drawing for minutes.
        stream.set_read_timeout(Some(Duration::from_secs(600))).expect("a timeout");
        let body = if body.is_null() { String::new() } else { body.to_string() };
        let request = format!(
            "{method} {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
            self.address,
            body.len()
        );
        std::io::Write::write_all(&mut stream, request.as_bytes()).expect("send to chromedriver");
        let answer = read_answer(&mut stream);
        let value: Value = serde_json::from_slice(&answer.body).expect("chromedriver answers JSON");
        assert_eq!(answer.status, 200, "WebDriver {method} {path}: {value}");
        value["value"].clone()
    }

    fn session_call(&self, method: &str, path: &str, body: &Value) -> Value {
        self.call(method, &format!("/session/{}{path}", self.session), body)
    }

    pub fn open(&self, url: &str) {
        self.session_call("POST", "/url", &json!({"url": url}));
    }

    /// Runs `script` (a function body; `arguments` are `args`) in the page and returns its value.
    pub fn run(&self, script: &str, args: &[Value]) -> Value {
        self.session_call("POST", "/execute/sync", &json!({"script": script, "args": args}))
    }

    /// Sets the window's outer size in CSS pixels.
    pub fn resize(&self, width: u32, height: u32) {
        self.session_call("POST", "/window/rect", &json!({"width": width, "height": height}));
    }

    /// A finger's drag on the element `selector` finds: down at its centre, moved by (dx, dy) in steps, up.
    pub fn touch_drag(&self, selector: &str, dx: i64, dy: i64) {
        let element = self.session_call("POST", "/element", &json!({"using": "css selector", "value": selector}));
        let origin = element.clone();
        let mut actions = vec![
            json!({"type": "pointerMove", "duration": 0, "origin": origin, "x": 0, "y": 0}),
            json!({"type": "pointerDown", "button": 0}),
        ];
        for step in 1..=5 {
            actions.push(json!({"type": "pointerMove", "duration": 50, "origin": origin, "x": dx * step / 5, "y": dy * step / 5}));
        }
        actions.push(json!({"type": "pointerUp", "button": 0}));
        let finger =
            json!({"type": "pointer", "id": "finger", "parameters": {"pointerType": "touch"}, "actions": actions});
        self.session_call("POST", "/actions", &json!({"actions": [finger]}));
        self.session_call("DELETE", "/actions", &Value::Null);
    }

    /// Runs `script` asynchronously (a function body whose last argument is the callback it calls with its
    /// value) and returns that value.
    pub fn run_async(&self, script: &str, args: &[Value]) -> Value {
        self.session_call("POST", "/execute/async", &json!({"script": script, "args": args}))
    }

    /// Polls `script` until it returns true, within `within`.
    pub fn wait_for(&self, what: &str, script: &str, within: Duration) {
        let started = Instant::now();
        while self.run(script, &[]) != json!(true) {
            assert!(started.elapsed() < within, "waited {within:?} for {what}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The page as a PNG.
    pub fn screenshot(&self) -> Vec<u8> {
        let encoded = self.session_call("GET", "/screenshot", &Value::Null);
        base64(encoded.as_str().expect("a screenshot"))
    }

    /// The console's messages since the last call: (level, text).
    pub fn console(&self) -> Vec<(String, String)> {
        let entries = self.session_call("POST", "/se/log", &json!({"type": "browser"}));
        entries
            .as_array()
            .map(|list| {
                list.iter()
                    .map(|e| {
                        (e["level"].as_str().unwrap_or("").to_string(), e["message"].as_str().unwrap_or("").to_string())
                    })
                    .collect()
            })
            .unwrap_or_default()
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // Ending the session ends the browser (chromedriver refuses a request whose Host is not its own).
        if !self.session.is_empty() {
            if let Ok(mut stream) = TcpStream::connect(self.address) {
                let request = format!(
                    "DELETE /session/{} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Length: 0\r\n\r\n",
                    self.session, self.address
                );
                let _ = stream.set_read_timeout(Some(Duration::from_secs(30)));
                if std::io::Write::write_all(&mut stream, request.as_bytes()).is_ok() {
                    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| read_answer(&mut stream)));
                }
            }
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// Standard base64 (WebDriver's screenshots, a canvas's data URL) decoded.
pub fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let sextets: Vec<u8> = text.bytes().filter_map(value).collect();
    let mut out = Vec::with_capacity(sextets.len() * 3 / 4);
    for group in sextets.chunks(4) {
        let bits = group.iter().enumerate().fold(0u32, |bits, (i, &s)| bits | u32::from(s) << (18 - 6 * i));
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..group.len()]);
    }
    out
}

/// Standard base64 encoded (a file handed to the page).
pub fn base64_encoded(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let bits = chunk.iter().enumerate().fold(0u32, |bits, (i, &b)| bits | u32::from(b) << (16 - 8 * i));
        for i in 0..=chunk.len() {
            out.push(ALPHABET[(bits >> (18 - 6 * i) & 63) as usize] as char);
        }
        for _ in chunk.len()..3 {
            out.push('=');
        }
    }
    out
}
