//! A small HTTP/1.1 server on the loopback address for `radiosity view`: it
//! answers GET and HEAD for the page's files and the bake, all held in
//! memory, and nothing else (no file of the disk is reachable through it).

use anyhow::{Context, Result};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::Arc;
use std::time::Duration;

/// Longest request head read (bytes); longer requests are refused.
const MAX_HEAD: usize = 16 * 1024;

/// How long a connection may take to send its request.
const READ_TIMEOUT: Duration = Duration::from_secs(10);

/// The files served: (path, content type, body).
pub struct Site {
    files: Vec<(String, String, Vec<u8>)>,
}

impl Site {
    /// A site of `files`, each `(path from /, content type, body)`; `/` is
    /// `index.html`.
    pub fn new(files: Vec<(String, String, Vec<u8>)>) -> Self {
        Site { files }
    }

    fn find(&self, path: &str) -> Option<&(String, String, Vec<u8>)> {
        let path = path.split(['?', '#']).next().unwrap_or("");
        let name = match path.trim_start_matches('/') {
            "" => "index.html",
            p => p,
        };
        self.files.iter().find(|(p, _, _)| p == name)
    }
}

/// Serves `site` on `listener` until the process ends, a thread per
/// connection.
pub fn serve(listener: TcpListener, site: Arc<Site>) -> Result<()> {
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue };
        let site = Arc::clone(&site);
        std::thread::spawn(move || {
            // A client that goes away mid-answer is no error of ours.
            let _ = answer(stream, &site);
        });
    }
    Ok(())
}

/// Reads one request from `stream` and answers it.
fn answer(mut stream: TcpStream, site: &Site) -> Result<()> {
    stream.set_read_timeout(Some(READ_TIMEOUT))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut head = Vec::new();
    loop {
        let mut line = Vec::new();
        let n = reader
            .by_ref()
            .take((MAX_HEAD + 1 - head.len().min(MAX_HEAD)) as u64)
            .read_until(b'\n', &mut line)
            .context("reading the request")?;
        head.extend_from_slice(&line);
        if n == 0 || line == b"\r\n" || line == b"\n" {
            break;
        }
        if head.len() > MAX_HEAD {
            return respond(
                &mut stream,
                "431 Request Header Fields Too Large",
                "text/plain",
                b"",
                true,
            );
        }
    }
    let text = String::from_utf8_lossy(&head);
    let mut words = text.lines().next().unwrap_or("").split_whitespace();
    let (method, path) = (words.next().unwrap_or(""), words.next().unwrap_or(""));
    let body = method != "HEAD";
    match (method, site.find(path)) {
        ("GET" | "HEAD", Some((_, kind, bytes))) => {
            respond(&mut stream, "200 OK", kind, bytes, body)
        }
        ("GET" | "HEAD", None) => respond(
            &mut stream,
            "404 Not Found",
            "text/plain",
            b"not found\n",
            body,
        ),
        _ => respond(
            &mut stream,
            "405 Method Not Allowed",
            "text/plain",
            b"GET or HEAD only\n",
            true,
        ),
    }
}

fn respond(
    stream: &mut TcpStream,
    status: &str,
    kind: &str,
    bytes: &[u8],
    body: bool,
) -> Result<()> {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: \
         no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        bytes.len()
    );
    stream.write_all(head.as_bytes())?;
    if body {
        stream.write_all(bytes)?;
    }
    stream.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    fn get(address: std::net::SocketAddr, request: &str) -> String {
        let mut s = TcpStream::connect(address).unwrap();
        s.write_all(request.as_bytes()).unwrap();
        let mut out = String::new();
        s.read_to_string(&mut out).unwrap();
        out
    }

    #[test]
    fn serves_its_files_and_nothing_else() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap();
        let site = Arc::new(Site::new(vec![
            (
                "index.html".into(),
                "text/html".into(),
                b"<p>hi</p>".to_vec(),
            ),
            (
                "scene.glb".into(),
                "model/gltf-binary".into(),
                vec![1, 2, 3],
            ),
        ]));
        std::thread::spawn(move || serve(listener, site));
        let index = get(address, "GET / HTTP/1.1\r\nHost: x\r\n\r\n");
        assert!(index.starts_with("HTTP/1.1 200 OK\r\n"), "{index}");
        assert!(index.contains("Content-Length: 9\r\n") && index.ends_with("<p>hi</p>"));
        let head = get(address, "HEAD /scene.glb?x=1 HTTP/1.1\r\n\r\n");
        assert!(head.contains("Content-Length: 3\r\n") && head.ends_with("\r\n\r\n"));
        for path in ["/../Cargo.toml", "/etc/passwd", "/index.htm"] {
            let r = get(address, &format!("GET {path} HTTP/1.1\r\n\r\n"));
            assert!(r.starts_with("HTTP/1.1 404"), "{path}: {r}");
        }
        let post = get(address, "POST / HTTP/1.1\r\n\r\n");
        assert!(post.starts_with("HTTP/1.1 405"), "{post}");
    }
}
