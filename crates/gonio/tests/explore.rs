//! `gonio explore`'s JSON API, driven over HTTP as the page drives it: values equal to the
//! command line's, errors naming the parameter and its range, paths confined to `--data`,
//! uploads size-limited, renders streamed and stopped when the client goes away.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running server, killed when dropped.
struct Server {
    child: Child,
    addr: String,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn serve(args: &[&str]) -> Server {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .args(["explore", "--port", "0"])
        .args(args)
        .stdout(Stdio::piped())
        .spawn()
        .expect("gonio explore starts");
    let mut line = String::new();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    out.read_line(&mut line).unwrap();
    // Keep reading what else it prints.
    std::thread::spawn(move || std::io::copy(&mut out, &mut std::io::sink()));
    let addr =
        line.split("http://").nth(1).and_then(|r| r.split('/').next()).expect("the address is printed").to_string();
    Server { child, addr }
}

/// One request; the status and body.
fn request(addr: &str, method: &str, path: &str, body: &[u8]) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    // HTTP/1.0: the reply is not chunked and ends when the connection closes.
    write!(s, "{method} {path} HTTP/1.0\r\nHost: {addr}\r\nContent-Length: {}\r\n\r\n", body.len()).unwrap();
    s.write_all(body).unwrap();
    let mut out = Vec::new();
    s.read_to_end(&mut out).unwrap();
    let split = out.windows(4).position(|w| w == b"\r\n\r\n").unwrap_or_else(|| panic!("{path}: no reply"));
    let status = String::from_utf8_lossy(&out[..split]).split(' ').nth(1).unwrap().parse().unwrap();
    (status, out[split + 4..].to_vec())
}

fn get(addr: &str, path: &str) -> (u16, serde_json::Value) {
    let (status, body) = request(addr, "GET", path, b"");
    (
        status,
        serde_json::from_slice(&body).unwrap_or_else(|e| panic!("{path}: {e}: {}", String::from_utf8_lossy(&body))),
    )
}

fn ok(addr: &str, path: &str) -> serde_json::Value {
    let (status, v) = get(addr, path);
    assert_eq!(status, 200, "{path}: {v}");
    v
}

fn gonio_json(args: &[&str]) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_gonio")).args(args).output().unwrap();
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gonio-explore-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn renders(addr: &str) -> u64 {
    ok(addr, "/api/status")["renders"].as_u64().unwrap()
}

fn wait_for_renders(addr: &str, n: u64) -> bool {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(10) {
        if renders(addr) == n {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    false
}

#[test]
fn the_page_and_the_model_panel_come_from_the_binary_and_the_registry() {
    let s = serve(&[]);
    let (status, page) = request(&s.addr, "GET", "/", b"");
    assert_eq!(status, 200);
    let page = String::from_utf8(page).unwrap();
    assert!(page.contains("gonio explore") && page.contains("/explore.js") && !page.contains("http"), "no CDN");
    for asset in ["/explore.js", "/lobe3d.js", "/explore.css"] {
        assert_eq!(request(&s.addr, "GET", asset, b"").0, 200, "{asset}");
    }
    assert_eq!(ok(&s.addr, "/api/models"), gonio_json(&["models", "--json"]));
    let (status, e) = get(&s.addr, "/nosuch");
    assert_eq!(status, 404, "{e}");
}

#[test]
fn values_equal_gonio_eval_and_the_plots_are_the_models() {
    let s = serve(&[]);
    let (wi, wo) = ("-0.5,0.1,0.86", "0.3,-0.2,0.9");
    let api = ok(&s.addr, &format!("/api/eval?m=ggx:alpha=0.3&m=ward&wi={wi}&wo={wo}"));
    for (i, (m, p)) in [("ggx", vec!["--alpha", "0.3"]), ("ward", vec![])].iter().enumerate() {
        let mut args = vec!["eval", m];
        args.extend(p.iter());
        args.extend(["--wi", wi, "--wo", wo, "--json"]);
        let cli = gonio_json(&args);
        assert_eq!(api["results"][i]["brdf"], cli["brdf"], "{m}");
        assert_eq!(api["results"][i]["pdf"], cli["pdf"], "{m}");
    }
    // The in-plane lobe at θo = 0 (index 180 of −90..90 by 0.5°) for θi = 30°: ρ of Lambert is albedo/π.
    let v = ok(&s.addr, "/api/views?m=lambert:albedo=0.6&ti=30&parts=polar,albedo,slice,lobe,fresnel");
    let m = &v["models"][0];
    let rho = m["polar"]["rho"][180].as_f64().unwrap();
    assert!((rho - 0.6 / std::f64::consts::PI).abs() < 1e-5, "{rho}");
    // Both albedo integrals of Lambert are its albedo (the cosine sampler is exact).
    for over in ["over_wi", "over_wo"] {
        for a in m["albedo"][over]["mean"].as_array().unwrap() {
            assert!((a.as_f64().unwrap() - 0.6).abs() < 1e-3, "{over}: {a}");
        }
    }
    assert!(m["fresnel"].is_null(), "Lambert has no interface");
    let g = ok(&s.addr, "/api/views?m=ggx&parts=fresnel");
    let names: Vec<&str> =
        g["models"][0]["fresnel"]["curves"].as_array().unwrap().iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["unpolarised", "Rs", "Rp", "Schlick"]);
}

#[test]
fn bad_input_is_a_400_naming_the_parameter_and_its_range() {
    let s = serve(&[]);
    let (status, e) = get(&s.addr, "/api/views?m=ggx:alpha=7");
    assert_eq!(
        (status, e["parameter"].as_str(), e["expected"].as_str()),
        (400, Some("alpha"), Some("[0.0001, 1]")),
        "{e}"
    );
    let (status, e) = get(&s.addr, "/api/views?m=ggx&ti=100");
    assert_eq!((status, e["parameter"].as_str()), (400, Some("ti")), "{e}");
    assert!(e["error"].as_str().unwrap().contains("[0, 89.9]"), "{e}");
    let (status, e) = get(&s.addr, "/api/views?m=nosuch");
    assert_eq!((status, e["parameter"].as_str()), (400, Some("model")), "{e}");
    assert!(e["expected"].as_str().unwrap().contains("lambert"), "{e}");
    let (status, e) = get(&s.addr, "/api/views?m=ggx:nosuch=1");
    assert_eq!((status, e["parameter"].as_str()), (400, Some("nosuch")), "{e}");
    let (status, e) = get(&s.addr, "/api/views");
    assert_eq!((status, e["parameter"].as_str()), (400, Some("m")), "{e}");
    let (status, e) = get(&s.addr, "/api/eval?m=ggx&wi=0,0,0&wo=0,0,1");
    assert_eq!((status, e["parameter"].as_str()), (400, Some("wi")), "{e}");
    let (status, e) = get(&s.addr, "/api/render?m=ggx&size=5000");
    assert_eq!((status, e["parameter"].as_str()), (400, Some("size")), "{e}");
    let (status, e) = get(&s.addr, "/api/fit?m=ggx&model=ward");
    assert_eq!(status, 400, "{e}");
    assert!(e["error"].as_str().unwrap().contains("not measured"), "{e}");
}

fn write_merl(dir: &Path) -> PathBuf {
    let bin = dir.join("gold.binary");
    let o = Command::new(env!("CARGO_BIN_EXE_gonio"))
        .args(["measure", "ggx", "--alpha", "0.2", "--diffuse", "0.2,0.1,0.05", "-o"])
        .arg(&bin)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    bin
}

#[test]
fn files_are_read_only_below_the_data_folders() {
    let base = scratch("confine");
    let data = base.join("data");
    std::fs::create_dir_all(&data).unwrap();
    write_merl(&data);
    std::fs::copy(data.join("gold.binary"), base.join("secret.binary")).unwrap();
    let s = serve(&["--data", data.to_str().unwrap()]);
    let files = ok(&s.addr, "/api/files");
    assert_eq!(files["measured"], serde_json::json!(["gold.binary"]));
    // Relative to the folder, or absolute below it.
    ok(&s.addr, "/api/views?m=merl:filename=gold.binary&parts=polar");
    ok(&s.addr, &format!("/api/views?m=merl:filename={}&parts=polar", data.join("gold.binary").display()));
    let secret = base.join("secret.binary");
    for name in ["../secret.binary".to_string(), secret.display().to_string(), "/etc/passwd".into()] {
        let (status, e) = get(&s.addr, &format!("/api/views?m=merl:filename={name}"));
        assert_eq!((status, e["parameter"].as_str()), (403, Some("filename")), "{name}: {e}");
        assert!(e["error"].as_str().unwrap().contains("--data"), "{e}");
    }
    let (status, e) = get(&s.addr, "/api/render?m=lambert&object=../secret.binary");
    assert_eq!(status, 403, "{e}");
    // Without --data nothing on disk can be opened.
    let bare = serve(&[]);
    let (status, e) = get(&bare.addr, &format!("/api/views?m=merl:filename={}", data.join("gold.binary").display()));
    assert_eq!(status, 403, "{e}");
    let _ = std::fs::remove_dir_all(&base);
}

#[test]
fn uploads_are_size_limited_and_checked_on_arrival() {
    let s = serve(&["--upload-limit", "2"]);
    // Refused from the header alone, before any of the body is read.
    let mut c = TcpStream::connect(&s.addr).unwrap();
    write!(
        c,
        "POST /api/upload?name=big.binary HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Length: 35000000\r\n\r\n",
        s.addr
    )
    .unwrap();
    let mut out = String::new();
    c.read_to_string(&mut out).unwrap();
    assert!(out.starts_with("HTTP/1.1 413"), "{out}");
    assert!(out.contains("limit"), "{out}");
    let (status, body) = request(&s.addr, "POST", "/api/upload?name=bad.binary", b"not a MERL file");
    assert_eq!(status, 400, "{}", String::from_utf8_lossy(&body));
    let (status, _) = request(&s.addr, "POST", "/api/upload?name=x.exe", b"hello");
    assert_eq!(status, 400);
    // A tabulated file measured by `gonio measure`, uploaded and used as a model.
    let dir = scratch("upload");
    let csv = dir.join("ward.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_gonio")).args(["measure", "ward", "-o"]).arg(&csv).output().unwrap();
    assert!(o.status.success());
    let (status, body) = request(&s.addr, "POST", "/api/upload?name=ward.csv", &std::fs::read(&csv).unwrap());
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    let up: serde_json::Value = serde_json::from_slice(&body).unwrap();
    let item = up["item"].as_str().unwrap();
    assert!(item.starts_with("tabulated:filename=upload/"), "{item}");
    let v = ok(&s.addr, &format!("/api/views?m={item}&ti=40&parts=polar"));
    let peak = v["models"][0]["polar"]["rho"].as_array().unwrap().iter().filter_map(|x| x.as_f64()).fold(0.0, f64::max);
    assert!(peak > 1.0, "the Ward lobe comes through the table: {peak}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Opens a render stream and reads its first frame; returns the open connection.
fn first_frame(addr: &str, query: &str) -> (TcpStream, [u32; 3]) {
    let mut s = TcpStream::connect(addr).unwrap();
    write!(s, "GET /api/render?{query} HTTP/1.1\r\nHost: {addr}\r\n\r\n").unwrap();
    let mut buf = Vec::new();
    let mut chunk = [0u8; 65536];
    let head_end = loop {
        let n = s.read(&mut chunk).unwrap();
        assert!(n > 0, "the stream ended early");
        buf.extend_from_slice(&chunk[..n]);
        if let Some(p) = buf.windows(4).position(|w| w == b"\r\n\r\n") {
            break p + 4;
        }
    };
    assert!(buf.starts_with(b"HTTP/1.1 200"), "{}", String::from_utf8_lossy(&buf[..head_end]));
    while buf.len() < head_end + 16 {
        let n = s.read(&mut chunk).unwrap();
        buf.extend_from_slice(&chunk[..n]);
    }
    let f = &buf[head_end..];
    assert_eq!(&f[..4], b"GNF1");
    let u = |k: usize| u32::from_le_bytes(f[4 + 4 * k..8 + 4 * k].try_into().unwrap());
    (s, [u(0), u(1), u(2)])
}

#[test]
fn renders_stream_frames_run_in_several_tabs_and_stop_when_the_client_goes() {
    let s = serve(&[]);
    assert_eq!(renders(&s.addr), 0);
    let (a, fa) = first_frame(&s.addr, "m=lambert&size=48&spp=60000&light=0.3,0.8,0.5");
    let (b, fb) = first_frame(&s.addr, "m=ggx:alpha=0.2&object=suzanne&size=32&spp=60000");
    assert_eq!((fa, fb), ([48, 48, 1], [32, 32, 1]));
    assert_eq!(renders(&s.addr), 2, "two tabs render at once");
    drop(a);
    assert!(wait_for_renders(&s.addr, 1), "the render of a closed connection stops");
    drop(b);
    assert!(wait_for_renders(&s.addr, 0));
    // A named render is stopped by a newer one of the same name, and by /api/stop.
    let (_c, _) = first_frame(&s.addr, "m=lambert&size=32&spp=60000&stream=tab1/lit");
    let (_d, _) = first_frame(&s.addr, "m=lambert&size=32&spp=60000&stream=tab1/lit");
    assert!(wait_for_renders(&s.addr, 1), "the newer render replaces the older");
    let (status, _) = request(&s.addr, "POST", "/api/stop?stream=tab1/lit", b"");
    assert_eq!(status, 200);
    assert!(wait_for_renders(&s.addr, 0), "/api/stop ends it");
}

#[test]
fn checks_fits_and_commands_are_the_command_lines() {
    let dir = scratch("fit");
    write_merl(&dir);
    let s = serve(&["--data", dir.to_str().unwrap()]);
    let c = ok(&s.addr, "/api/check?m=phong&ti=40");
    let props: Vec<&str> = c["findings"].as_array().unwrap().iter().map(|f| f["property"].as_str().unwrap()).collect();
    assert_eq!(props, ["non-negativity", "reciprocity", "energy", "isotropy", "sample/pdf/eval", "chi-square"]);
    let cli = gonio_json(&["check", "phong", "--json"]);
    assert_eq!(c["findings"], cli["cases"][0]["findings"], "the same verdicts as gonio check");
    let p = c["chi2"]["p_value"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&p) && c["cloud"].as_array().unwrap().len() > 100, "{p}");
    let f = ok(&s.addr, "/api/fit?m=merl:filename=gold.binary&model=ggx");
    let alpha: f64 =
        f["item"].as_str().unwrap().split(":alpha=").nth(1).unwrap().split(':').next().unwrap().parse().unwrap();
    assert!((alpha - 0.2).abs() < 0.01, "{f}");
    let r = ok(&s.addr, &format!("/api/residual?m=merl:filename=gold.binary&f={}", f["item"].as_str().unwrap()));
    let worst =
        r["log10_ratio"].as_array().unwrap().iter().filter_map(|v| v.as_f64()).fold(0.0, |a: f64, b| a.max(b.abs()));
    assert!(worst > 0.0 && worst < 1.0, "{worst}");
    // The eval line runs and gives the page's value.
    let cmd = ok(&s.addr, "/api/command?m=ggx:alpha=0.3&ti=30&wi=-0.5,0,0.866025&wo=0.3,0,0.953939");
    let line = cmd["eval"].as_str().unwrap();
    let words: Vec<&str> = line.split_whitespace().skip(1).chain(["--json"]).collect();
    let page = ok(&s.addr, "/api/eval?m=ggx:alpha=0.3&wi=-0.5,0,0.866025&wo=0.3,0,0.953939");
    assert_eq!(gonio_json(&words)["brdf"], page["results"][0]["brdf"], "{line}");
    assert!(cmd["plot"]["polar"].as_str().unwrap().contains("--theta-i 30"), "{cmd}");
    assert!(cmd["mitsuba"].as_str().unwrap().contains("<!--"), "ggx's default shadowing has no Mitsuba form: {cmd}");
    let d = ok(&s.addr, "/api/command?m=dielectric");
    assert!(d["mitsuba"].as_str().unwrap().starts_with("<bsdf type=\"dielectric\">"), "{d}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn foreign_hosts_and_origins_odd_values_and_repeated_parameters_are_refused() {
    let dir = scratch("refuse");
    write_merl(&dir);
    let s = serve(&["--data", dir.to_str().unwrap()]);
    // A web site reaching the server through a rebound DNS name, or posting from its page.
    let mut c = TcpStream::connect(&s.addr).unwrap();
    write!(c, "GET /api/files HTTP/1.0\r\nHost: evil.example:80\r\n\r\n").unwrap();
    let mut out = String::new();
    c.read_to_string(&mut out).unwrap();
    assert!(out.starts_with("HTTP/1.0 403") && !out.contains(dir.to_str().unwrap()), "{out}");
    let mut c = TcpStream::connect(&s.addr).unwrap();
    let head = format!("POST /api/stop?stream=x HTTP/1.0\r\nHost: {}\r\nOrigin: http://evil.example\r\n", s.addr);
    write!(c, "{head}Content-Length: 0\r\n\r\n").unwrap();
    let mut out = String::new();
    c.read_to_string(&mut out).unwrap();
    assert!(out.starts_with("HTTP/1.0 403"), "{out}");
    for (path, param) in [
        ("/api/views?m=ggx&ti=NaN", "ti"),
        ("/api/views?m=ggx&ti=", "ti"),
        ("/api/views?m=ggx&phid=1e400", "phid"),
        ("/api/views?m=ggx:alpha=nan", "alpha"),
        ("/api/views?m=merl:filename=gold.binary:filename=/etc/passwd", "filename"),
        ("/api/render?m=lambert&stream=", "stream"),
        ("/api/render?m=lambert&light=1,2", "light"),
        ("/api/render?m=lambert&probe=../x.hdr", "probe"),
        ("/api/views?m=ggx&parts=polar,nosuch", "parts"),
    ] {
        let (status, e) = get(&s.addr, path);
        assert!((400..=404).contains(&status) && e["parameter"] == param, "{path}: {status} {e}");
    }
    let (status, _) = request(&s.addr, "POST", "/api/stop?stream=", b"");
    assert_eq!(status, 400);
    let (status, e) = get(&s.addr, "/api/upload");
    assert_eq!(status, 405, "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
