//! `gonio explore`: a local web page to turn a model's knobs and watch its lobe, its checks and
//! a lit object change. The page (HTML, JS, CSS) is embedded in the binary; it talks to a small
//! JSON API served here by tiny_http, one thread per request (the work is CPU-bound model
//! evaluation and rendering, which needs no async runtime), so several tabs work at once.

pub mod cache;
pub mod checks;
pub mod command;
pub mod files;
pub mod fitting;
pub mod http;
pub mod lit;
pub mod model;
pub mod views;

use anyhow::{Context, Result};
use clap::Args;
use files::{Files, Kind};
use http::{bytes, json, ApiError, Query, Reply};
use model::{resolve, resolve_all, TableCache};
use serde_json::json as j;
use std::io::{Read, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// `gonio explore`.
#[derive(Debug, Args)]
pub struct ExploreArgs {
    /// Port to listen on (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8686)]
    pub port: u16,
    /// Address to listen on; the default serves this machine only.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: String,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// A folder whose MERL, tabulated, mesh and probe files the page may open (repeatable);
    /// nothing outside these folders can be read.
    #[arg(long, value_name = "DIR")]
    pub data: Vec<PathBuf>,
    /// Largest upload accepted, in MiB.
    #[arg(long, default_value_t = 64, value_name = "MIB")]
    pub upload_limit: u64,
}

const INDEX_HTML: &str = include_str!("../../web/index.html");
const EXPLORE_JS: &str = include_str!("../../web/explore.js");
const LOBE3D_JS: &str = include_str!("../../web/lobe3d.js");
const EXPLORE_CSS: &str = include_str!("../../web/explore.css");

/// What every request thread shares.
struct State {
    /// The `Host` values served (None: any, when bound beyond loopback).
    hosts: Option<Vec<String>>,
    files: Files,
    tables: TableCache,
    assets: lit::Assets,
    renders: AtomicUsize,
    streams: lit::Streams,
}

/// Runs the server until the process is stopped.
pub fn run(args: &ExploreArgs) -> Result<()> {
    let files = Files::new(&args.data, args.upload_limit.saturating_mul(1 << 20))?;
    let addr = format!("{}:{}", args.bind, args.port);
    let listener = std::net::TcpListener::bind((args.bind.as_str(), args.port))
        .with_context(|| format!("cannot listen on {addr}"))?;
    no_delay(&listener);
    let server =
        tiny_http::Server::from_listener(listener, None).map_err(|e| anyhow::anyhow!("cannot serve on {addr}: {e}"))?;
    let local = server.server_addr().to_ip().context("the server has no IP address")?;
    let url = format!("http://{local}/");
    // On a loopback address only requests naming it are served, so that a web site cannot reach
    // the server through a DNS name rebound to 127.0.0.1.
    let hosts = local.ip().is_loopback().then(|| {
        let p = local.port();
        vec![format!("localhost:{p}"), format!("127.0.0.1:{p}"), format!("[::1]:{p}")]
    });
    // Not outln!: a server whose stdout was closed (`| head -1`) keeps serving.
    let mut out = std::io::stdout();
    let _ = writeln!(out, "gonio explore: serving {url} (Ctrl-C to stop)");
    for root in files.roots() {
        let _ = writeln!(out, "  data folder {}", root.display());
    }
    let _ = out.flush();
    if args.open {
        open_browser(&url);
    }
    let state = Arc::new(State {
        hosts,
        files,
        tables: TableCache::default(),
        assets: lit::Assets::default(),
        renders: AtomicUsize::new(0),
        streams: lit::Streams::default(),
    });
    for request in server.incoming_requests() {
        let state = state.clone();
        std::thread::spawn(move || handle(&state, request));
    }
    Ok(())
}

/// Sets TCP_NODELAY on the listening socket, which the accepted connections inherit: tiny_http
/// writes a reply's head and body separately, and with Nagle's algorithm the body's last
/// segment would wait for the browser's delayed acknowledgement, 40 ms a request.
fn no_delay(listener: &std::net::TcpListener) {
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        let on: libc::c_int = 1;
        // SAFETY: a valid socket descriptor, and an option value of the size passed.
        unsafe {
            libc::setsockopt(
                listener.as_raw_fd(),
                libc::IPPROTO_TCP,
                libc::TCP_NODELAY,
                (&on as *const libc::c_int).cast(),
                std::mem::size_of::<libc::c_int>() as libc::socklen_t,
            );
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = listener;
}

fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(opener).arg(url).spawn() {
        eprintln!("gonio explore: cannot open a browser ({opener}: {e}); open {url} yourself");
    }
}

/// Lowers this thread's scheduling priority to `nice`, for work that may take seconds (renders,
/// checks, fits): on Linux nice is per thread and the render's worker threads, created from
/// this one, inherit it, so the plots a slider move asks for are computed first.
pub(super) fn background(nice: i32) {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority only reads its integer arguments; a failure leaves the priority as it was.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, libc::gettid() as libc::id_t, nice);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = nice;
}

/// Refuses a request for another host name (DNS rebinding), and a POST from another site's page.
fn same_origin(state: &State, request: &tiny_http::Request) -> Result<(), ApiError> {
    let header = |name: &'static str| {
        request.headers().iter().find(|h| h.field.equiv(name)).map(|h| h.value.as_str().to_string())
    };
    let host = header("Host").unwrap_or_default();
    if let Some(hosts) = &state.hosts {
        if !hosts.contains(&host) {
            return Err(ApiError::new(
                403,
                format!("requests must name this machine (Host: {}), not '{host}'", hosts[1]),
            ));
        }
    }
    match header("Origin") {
        Some(o) if *request.method() == tiny_http::Method::Post && o != format!("http://{host}") => {
            Err(ApiError::new(403, format!("a page from {o} cannot change this server")))
        }
        _ => Ok(()),
    }
}

fn handle(state: &State, mut request: tiny_http::Request) {
    if let Err(e) = same_origin(state, &request) {
        let _ = request.respond(e.reply());
        return;
    }
    let (path, q) = Query::split(request.url());
    // Plots and a lit view's first frame first, then the lit views' refinement (lit::stream
    // lowers itself), then checks and fits (a second or more each).
    if matches!(path.as_str(), "/api/check" | "/api/fit") {
        background(19);
    }
    let method = request.method().clone();
    if path == "/api/render" {
        // Streamed: the reply is written straight to the socket, frame after frame. The render
        // is registered before its scene is built, so that requests supersede one another in
        // the order they arrived.
        let job = q.stream().and_then(|id| {
            if state.renders.load(Ordering::SeqCst) >= lit::MAX_RENDERS {
                return Err(ApiError::new(
                    503,
                    format!("{} renders are running; close a tab or wait", lit::MAX_RENDERS),
                ));
            }
            let cancel = state.streams.start(id);
            let r = resolve(&state.files, &state.tables, "m", q.get("m").unwrap_or_default())?;
            Ok((state.assets.job(&state.files, &r, &q)?, cancel))
        });
        match job {
            Err(e) => {
                let _ = request.respond(e.reply());
            }
            Ok((job, cancel)) => {
                let mut w = request.into_writer();
                let head = "HTTP/1.1 200 OK\r\nContent-Type: application/octet-stream\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
                if w.write_all(head.as_bytes()).and_then(|()| w.flush()).is_ok() {
                    lit::stream(job, &mut *w, &state.renders, cancel);
                }
            }
        }
        return;
    }
    let reply = match (method, path.as_str()) {
        (tiny_http::Method::Post, "/api/upload") => upload(state, &mut request, &q),
        (tiny_http::Method::Post, "/api/stop") => {
            let ids = q.all("stream");
            if ids.contains(&"") {
                Err(ApiError::param("stream", "", "a non-empty name"))
            } else {
                ids.iter().for_each(|id| state.streams.stop(id));
                Ok(json(200, &j!({ "stopped": ids })))
            }
        }
        (tiny_http::Method::Get, p) => get(state, p, &q),
        (m, p) => Err(ApiError::new(
            405,
            format!("{m} {p} is not served; the API takes GET, and POST for /api/upload and /api/stop"),
        )),
    };
    let _ = request.respond(reply.unwrap_or_else(|e| e.reply()));
}

fn get(state: &State, path: &str, q: &Query) -> Result<Reply, ApiError> {
    let (f, t) = (&state.files, &state.tables);
    let first = || resolve(f, t, "m", q.get("m").unwrap_or_default());
    Ok(match path {
        "/" | "/index.html" => bytes(200, "text/html; charset=utf-8", INDEX_HTML.into()),
        "/explore.js" => bytes(200, "text/javascript; charset=utf-8", EXPLORE_JS.into()),
        "/lobe3d.js" => bytes(200, "text/javascript; charset=utf-8", LOBE3D_JS.into()),
        "/explore.css" => bytes(200, "text/css; charset=utf-8", EXPLORE_CSS.into()),
        "/api/models" => json(200, &crate::cmd::models::models_json()),
        "/api/files" => json(200, &files_json(f)),
        "/api/status" => json(200, &j!({ "renders": state.renders.load(Ordering::SeqCst) })),
        "/api/views" => json(200, &views::views(&resolve_all(f, t, &q.all("m"))?, q)?),
        "/api/eval" => json(200, &eval(&resolve_all(f, t, &q.all("m"))?, q)?),
        "/api/check" => json(200, &checks::checks(&first()?, q)?),
        "/api/fit" => json(200, &fitting::fit(&first()?, q)?),
        "/api/residual" => {
            let fitted = resolve(f, t, "f", q.required("f", "the fitted model")?)?;
            json(200, &fitting::residual(&first()?, &fitted, q)?)
        }
        "/api/command" => json(200, &command::commands(&first()?, q)?),
        "/api/upload" | "/api/stop" => return Err(ApiError::new(405, format!("{path} takes POST"))),
        _ => return Err(ApiError::new(404, format!("nothing is served at '{path}'"))),
    })
}

fn files_json(f: &Files) -> serde_json::Value {
    let list = f.list();
    let of = |k: Kind| list.iter().filter(|(_, kind)| *kind == k).map(|(n, _)| n.clone()).collect::<Vec<_>>();
    j!({
        "roots": f.roots().iter().map(|r| r.display().to_string()).collect::<Vec<_>>(),
        "measured": of(Kind::Merl).into_iter().chain(of(Kind::Tabulated)).collect::<Vec<_>>(),
        "meshes": of(Kind::Mesh),
        "probes": of(Kind::Probe),
        "upload_limit": f.upload_limit,
    })
}

/// ρ and pdf of each model at directions written as `gonio eval` takes them.
fn eval(models: &[model::Resolved], q: &Query) -> Result<serde_json::Value, ApiError> {
    let (wi, wo) = (http::direction(q, "wi")?, http::direction(q, "wo")?);
    let results = models
        .iter()
        .map(|r| {
            Ok(j!({
                "model": r.arg.spec.name,
                "params": crate::modelarg::params_json(&r.arg.resolved()?),
                "brdf": r.brdf.eval(wi, wo).0,
                "pdf": r.brdf.pdf(wi, wo),
                "has_delta": r.brdf.has_delta(),
            }))
        })
        .collect::<Result<Vec<_>, ApiError>>()?;
    Ok(j!({ "wi": wi.to_array(), "wo": wo.to_array(), "results": results }))
}

fn upload(state: &State, request: &mut tiny_http::Request, q: &Query) -> Result<Reply, ApiError> {
    let name = q.required("name", "the file's name, e.g. name=gold.binary")?;
    let kind = Kind::of(name)
        .filter(|k| *k != Kind::Probe)
        .ok_or_else(|| ApiError::param("name", name, "a .binary (MERL), .csv/.txt (tabulated), .obj or .ply file"))?;
    let limit = state.files.upload_limit;
    let too_big = |n: u64| {
        ApiError::new(
            413,
            format!(
                "the upload is {n} bytes; the limit is {limit} bytes (start gonio explore with --upload-limit MIB)"
            ),
        )
    };
    if let Some(n) = request.body_length() {
        if n as u64 > limit {
            return Err(too_big(n as u64));
        }
    }
    let mut body = Vec::new();
    request
        .as_reader()
        .take(limit + 1)
        .read_to_end(&mut body)
        .map_err(|e| ApiError::new(400, format!("the upload was cut off: {e}")))?;
    if body.len() as u64 > limit {
        return Err(too_big(body.len() as u64));
    }
    // Parsed before it is kept, so a bad file is reported now and evicts no good upload.
    let body = Arc::new(body);
    let measured = match kind {
        Kind::Merl | Kind::Tabulated => {
            Some(model::read_measured(kind.name(), name, &files::Source::Upload(body.clone()))?)
        }
        _ => {
            render::io::parse_mesh(&body, name).map_err(|e| ApiError::new(400, e).named("file"))?;
            None
        }
    };
    let path = state.files.add_upload(name, body);
    let Some(m) = measured else { return Ok(json(200, &j!({ "name": path, "kind": kind.name() }))) };
    state.tables.insert(path.clone(), m);
    let item = format!("{}:filename={path}", kind.name());
    Ok(json(200, &j!({ "name": path, "kind": kind.name(), "item": item })))
}
