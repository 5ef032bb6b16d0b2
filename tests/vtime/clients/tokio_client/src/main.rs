//! A vehicle client on tokio's multi-thread runtime, as a Rust integrator would write one: a
//! reader task answers each control message at once; a keep-alive task on a 10 ms interval
//! repeats the latest pair when nothing was sent for 10 ms. They share the pair and the write
//! half under a tokio Mutex, and run on two worker threads (their parking: futex waits through
//! syscall(), the shim's to wrap). It reconnects when the connection ends.
//!
//!     ocp_tokio_client HOST:PORT
use std::sync::Arc;
use std::time::Duration;

use serde_json::{json, Value};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::tcp::OwnedWriteHalf;
use tokio::net::TcpStream;
use tokio::sync::Mutex;
use tokio::time::{interval, sleep, Instant, MissedTickBehavior};

const MAX_PAYLOAD: u32 = 16384;
const RESPONSE_PERIOD: Duration = Duration::from_millis(10);

struct Shared {
    writer: OwnedWriteHalf,
    pair: Option<(Value, Value)>, // ack_time (a u64, kept exact) and ack_time_mac
    received: u64,
    last_sent: Instant,
}

async fn respond(shared: &mut Shared) -> std::io::Result<()> {
    let (time, mac) = match &shared.pair {
        Some(pair) => pair.clone(),
        None => return Ok(()),
    };
    let response = json!({
        "ack_time": time,
        "ack_time_mac": mac,
        "vehicle_user_data": {"pos": null, "user_data": {"messages_received": shared.received}},
    });
    let payload = serde_json::to_vec(&response).expect("a response always serialises");
    let mut frame = (payload.len() as u32).to_le_bytes().to_vec();
    frame.extend_from_slice(&payload);
    shared.writer.write_all(&frame).await?;
    shared.last_sent = Instant::now();
    Ok(())
}

async fn keep_alive(shared: Arc<Mutex<Shared>>) {
    let mut ticks = interval(RESPONSE_PERIOD);
    ticks.set_missed_tick_behavior(MissedTickBehavior::Delay);
    loop {
        ticks.tick().await;
        let mut shared = shared.lock().await;
        if shared.last_sent.elapsed() >= RESPONSE_PERIOD && respond(&mut shared).await.is_err() {
            return;
        }
    }
}

async fn session(stream: TcpStream) -> std::io::Result<()> {
    stream.set_nodelay(true)?;
    let (mut reader, writer) = stream.into_split();
    let shared = Arc::new(Mutex::new(Shared { writer, pair: None, received: 0, last_sent: Instant::now() }));
    let timer = tokio::spawn(keep_alive(shared.clone()));
    let result = async {
        loop {
            let mut length = [0u8; 4];
            reader.read_exact(&mut length).await?;
            let length = u32::from_le_bytes(length);
            if length > MAX_PAYLOAD {
                return Err(std::io::Error::new(std::io::ErrorKind::InvalidData, "oversized frame"));
            }
            let mut payload = vec![0u8; length as usize];
            reader.read_exact(&mut payload).await?;
            let message: Value = serde_json::from_slice(&payload)?;
            let pair = match (message.get("ack_time"), message.get("ack_time_mac")) {
                (Some(time), Some(mac)) => (time.clone(), mac.clone()),
                _ => continue,
            };
            let mut shared = shared.lock().await;
            shared.pair = Some(pair);
            shared.received += 1;
            respond(&mut shared).await?;
        }
    }
    .await;
    timer.abort();
    result
}

async fn run(address: String) {
    let mut backoff = Duration::from_millis(100);
    loop {
        match TcpStream::connect(&address).await {
            Ok(stream) => {
                eprintln!("connected to {address}");
                backoff = Duration::from_millis(100);
                let reason = session(stream).await;
                eprintln!("disconnected ({reason:?}); reconnecting in {backoff:?}");
            }
            Err(error) => eprintln!("cannot connect ({error}); retrying in {backoff:?}"),
        }
        sleep(backoff).await;
        backoff = (backoff * 2).min(Duration::from_secs(2));
    }
}

const USAGE: &str = "usage: ocp_tokio_client HOST:PORT\n  a vehicle client on a tokio multi-thread runtime (2 workers): answers each control message at once, repeats the latest pair after 10 ms of silence, reconnects";

// The one argument, HOST:PORT; --help prints the usage (exit 0); anything else is exit 2, named.
fn address_from_arguments(args: &[String]) -> String {
    if args.len() == 2 && (args[1] == "--help" || args[1] == "-h") {
        println!("{USAGE}");
        std::process::exit(0);
    }
    let refuse = |why: String| -> ! {
        eprintln!("ocp_tokio_client: {why}\n{USAGE}");
        std::process::exit(2);
    };
    if let Some(option) = args.iter().skip(1).find(|arg| arg.starts_with('-')) {
        refuse(format!("unknown option {option}"));
    }
    if args.len() != 2 {
        refuse(format!("expected one HOST:PORT, got {} arguments", args.len() - 1));
    }
    match args[1].rsplit_once(':').map(|(_, port)| port.parse::<u16>()) {
        Some(Ok(port)) if port > 0 => args[1].clone(),
        _ => refuse(format!("{} is not HOST:PORT with a port in 1..65535", args[1])),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let address = address_from_arguments(&args);
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("the tokio runtime");
    runtime.block_on(run(address));
}
