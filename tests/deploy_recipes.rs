//! The scheduler recipes in `deploy/`, tested as far as this machine allows (no Slurm, no
//! Kubernetes, no container daemon): the Slurm array scripts run as shell scripts with the
//! variables Slurm sets, relief from the test build on PATH; the Kubernetes manifests parse, say
//! what an indexed Job needs, and their commands run in `sh` with the variables the Job sets; and
//! the container file is linted for what it must do. `RELIEF_CONTAINER_BUILD=1` also builds the
//! image where `docker` or `podman` reaches a daemon (minutes: it compiles relief).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_yaml::Value;

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// PATH with the test build's `relief` first.
fn path_with_relief() -> String {
    let bin = Path::new(env!("CARGO_BIN_EXE_relief"))
        .parent()
        .expect("the binary's folder")
        .to_owned();
    let rest = std::env::var("PATH").unwrap_or_default();
    format!("{}:{rest}", bin.display())
}

/// Runs `program args` with `env` and relief on PATH; fails the test unless it succeeds.
fn run(program: &str, args: &[&str], env: &[(&str, &str)]) -> Output {
    let out = Command::new(program)
        .args(args)
        .envs(env.iter().copied())
        .env("PATH", path_with_relief())
        .env("RELIEF_VALIDATION", "0")
        .output()
        .expect("the shell runs");
    assert!(
        out.status.success(),
        "{program} {args:?} with {env:?} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A sweep of a few seconds.
const TINY: &[&str] = &[
    "--quick",
    "--methods",
    "pom,qdm",
    "--sizes",
    "32",
    "--angles",
    "30",
    "--depth-scales",
    "0.1",
    "--no-stability",
    "--no-shading",
    "--no-lod",
    "--no-edits",
    "--no-blending",
    "--no-scene-shadows",
];

fn merged_results(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("merged/results.json")).expect("merged results");
    serde_json::from_str(&text).expect("JSON")
}

#[test]
fn the_slurm_scripts_are_valid_bash() {
    for script in ["bench-shards", "bench-merge", "render-frames"] {
        let file = repo(&format!("deploy/slurm/{script}.sbatch"));
        run("bash", &["-n", file.to_str().unwrap()], &[]);
        let text = std::fs::read_to_string(&file).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        // sbatch reads #SBATCH lines only before the first command.
        let first_command = lines
            .iter()
            .position(|l| !l.trim().is_empty() && !l.starts_with('#'))
            .unwrap();
        let last_directive = lines
            .iter()
            .rposition(|l| l.starts_with("#SBATCH"))
            .unwrap();
        assert!(
            last_directive < first_command,
            "{script}: #SBATCH after a command"
        );
    }
}

#[test]
fn a_slurm_array_of_shards_and_its_merge_make_one_sweep() {
    if common::device("slurm_bench_shards").is_none() {
        return;
    }
    let dir = common::scratch_dir("deploy-slurm-bench");
    let out = dir.to_str().unwrap();
    let shards = repo("deploy/slurm/bench-shards.sbatch");
    // --array=0-1: indices from 0, as some sites number them.
    for id in ["0", "1"] {
        let mut args = vec![shards.to_str().unwrap(), out];
        args.extend_from_slice(TINY);
        let env = [
            ("SLURM_ARRAY_TASK_ID", id),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ];
        run("bash", &args, &env);
    }
    assert!(dir.join("shard-1-of-2/results.json").exists());
    assert!(dir.join("shard-2-of-2/results.json").exists());
    let merge = repo("deploy/slurm/bench-merge.sbatch");
    run("bash", &[merge.to_str().unwrap(), out], &[]);
    let merged = merged_results(&dir);
    assert!(merged.get("shard").is_none());
    assert!(!merged["runs"].as_array().unwrap().is_empty());
}

#[test]
fn a_slurm_array_renders_a_sequence_in_parts() {
    if common::device("slurm_render_frames").is_none() {
        return;
    }
    let dir = common::scratch_dir("deploy-slurm-render");
    let out = dir.join("shots/f.png");
    let script = repo("deploy/slurm/render-frames.sbatch");
    // Three frames over two tasks: 1..2 and 3..3; task 5 of 5 (a frame each) finds none left.
    for (id, count) in [("1", "2"), ("2", "2"), ("5", "5")] {
        let args = [
            script.to_str().unwrap(),
            "3",
            out.to_str().unwrap(),
            "--width",
            "24",
            "--height",
            "16",
            "--orbit",
            "90",
        ];
        let env = [
            ("SLURM_ARRAY_TASK_ID", id),
            ("SLURM_ARRAY_TASK_COUNT", count),
        ];
        run("bash", &args, &env);
    }
    for k in 1..=3 {
        assert!(
            dir.join(format!("shots/f_{k:04}.png")).exists(),
            "frame {k}"
        );
    }
    assert!(!dir.join("shots/f_0004.png").exists());
}

/// The manifest's first document.
fn manifest(name: &str) -> Value {
    let text = std::fs::read_to_string(repo(&format!("deploy/k8s/{name}"))).expect("manifest");
    serde_yaml::from_str(&text).unwrap_or_else(|e| panic!("{name} is not YAML: {e}"))
}

/// The Job's only container.
fn container(job: &Value) -> &Value {
    let containers = job["spec"]["template"]["spec"]["containers"]
        .as_sequence()
        .expect("containers");
    assert_eq!(containers.len(), 1);
    &containers[0]
}

/// The container's `env` as pairs.
fn env_of(container: &Value) -> Vec<(String, String)> {
    container["env"]
        .as_sequence()
        .expect("env")
        .iter()
        .map(|e| {
            let value = e["value"].as_str().expect("plain values").to_owned();
            (e["name"].as_str().expect("a name").to_owned(), value)
        })
        .collect()
}

/// Runs the container's `sh -c` script with its env, `results` standing in for the volume and
/// `extra` for what Kubernetes adds.
fn run_container(container: &Value, results: &Path, extra: &[(&str, &str)]) {
    let command: Vec<&str> = container["command"]
        .as_sequence()
        .expect("a command")
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    assert_eq!(command, ["/bin/sh", "-c"]);
    let script = container["args"][0].as_str().expect("one script");
    let mut env: Vec<(String, String)> = env_of(container)
        .into_iter()
        .map(|(k, v)| match k.as_str() {
            "RESULTS" => (k, results.display().to_string()),
            "RELIEF_BENCH_FLAGS" => (k, TINY.join(" ")),
            _ => (k, v),
        })
        .collect();
    env.extend(extra.iter().map(|(k, v)| ((*k).into(), (*v).into())));
    let env: Vec<(&str, &str)> = env.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    run("sh", &["-c", script], &env);
}

#[test]
fn the_kubernetes_manifests_describe_an_indexed_job_and_its_merge() {
    let volume = manifest("results-volume.yaml");
    assert_eq!(volume["kind"], "PersistentVolumeClaim");
    assert_eq!(volume["spec"]["accessModes"][0], "ReadWriteMany");
    let claim = volume["metadata"]["name"].as_str().unwrap();
    for name in ["bench-shards.yaml", "bench-merge.yaml"] {
        let job = manifest(name);
        assert_eq!(job["apiVersion"], "batch/v1", "{name}");
        assert_eq!(job["kind"], "Job", "{name}");
        let pod = &job["spec"]["template"]["spec"];
        assert_eq!(pod["restartPolicy"], "Never", "{name}");
        assert_eq!(
            pod["volumes"][0]["persistentVolumeClaim"]["claimName"],
            claim
        );
        let c = container(&job);
        let mount = c["volumeMounts"][0]["mountPath"].as_str().unwrap();
        let env = env_of(c);
        assert!(
            env.contains(&("RESULTS".into(), mount.into())),
            "{name}: {env:?}"
        );
    }
    let job = manifest("bench-shards.yaml");
    let spec = &job["spec"];
    assert_eq!(spec["completionMode"], "Indexed");
    let completions = spec["completions"].as_u64().expect("completions");
    assert_eq!(spec["parallelism"].as_u64(), Some(completions));
    let env = env_of(container(&job));
    assert!(
        env.contains(&("SHARDS".into(), completions.to_string())),
        "SHARDS must equal completions: {env:?}"
    );
}

#[test]
fn the_kubernetes_jobs_commands_run_a_sweep_and_merge_it() {
    if common::device("kubernetes_commands").is_none() {
        return;
    }
    let dir = common::scratch_dir("deploy-k8s");
    let shards = manifest("bench-shards.yaml");
    let completions = shards["spec"]["completions"].as_u64().unwrap();
    for index in 0..completions {
        let index = index.to_string();
        run_container(
            container(&shards),
            &dir,
            &[("JOB_COMPLETION_INDEX", &index)],
        );
    }
    run_container(container(&manifest("bench-merge.yaml")), &dir, &[]);
    let merged = merged_results(&dir);
    assert!(merged.get("shard").is_none());
    assert!(!merged["runs"].as_array().unwrap().is_empty());
}

#[test]
fn the_container_file_builds_relief_on_debian_with_lavapipe() {
    let file = repo("deploy/Containerfile");
    let text = std::fs::read_to_string(&file).expect("deploy/Containerfile");
    // Instructions, continuation lines joined.
    let joined = text.replace("\\\n", " ");
    let instructions: Vec<(&str, &str)> = joined
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| l.split_once(' ').unwrap_or((l, "")))
        .collect();
    let known = ["FROM", "WORKDIR", "COPY", "RUN", "ENV", "ENTRYPOINT", "CMD"];
    for (word, _) in &instructions {
        assert!(known.contains(word), "unexpected instruction {word}");
    }
    let froms: Vec<&str> = instructions
        .iter()
        .filter(|(w, _)| *w == "FROM")
        .map(|(_, rest)| *rest)
        .collect();
    assert_eq!(froms.len(), 2, "a build stage and a runtime stage");
    assert!(
        froms[0].starts_with("rust:")
            && froms[0].contains("bookworm")
            && froms[0].ends_with(" AS build")
    );
    assert!(froms[1].starts_with("debian:bookworm"), "{}", froms[1]);
    let runs: Vec<&str> = instructions
        .iter()
        .filter(|(w, _)| *w == "RUN")
        .map(|(_, rest)| *rest)
        .collect();
    assert!(runs
        .iter()
        .any(|r| r.contains("cargo build --release --locked --bin relief")));
    let apt = runs
        .iter()
        .find(|r| r.contains("apt-get install"))
        .expect("the runtime's packages");
    for needed in [
        "apt-get update",
        "--no-install-recommends",
        "libvulkan1",
        "mesa-vulkan-drivers",
        "rm -rf /var/lib/apt/lists",
    ] {
        assert!(apt.contains(needed), "{needed} in {apt}");
    }
    // Debian 12's own lavapipe (Mesa 22.3.6) leaks every frame: the image takes Mesa, and the
    // libdrm it needs, from Debian's backports of the same release.
    assert!(
        apt.contains("bookworm-backports main")
            && apt.contains("-t bookworm-backports")
            && apt.contains("libdrm2"),
        "lavapipe from bookworm-backports in {apt}"
    );
    assert!(instructions.contains(&(
        "COPY",
        "--from=build /src/target/release/relief /usr/local/bin/relief"
    )));
    assert!(instructions.contains(&("ENTRYPOINT", r#"["relief"]"#)));
    let caps = instructions
        .iter()
        .find(|(w, rest)| *w == "ENV" && rest.starts_with("NVIDIA_DRIVER_CAPABILITIES="))
        .expect("the NVIDIA runtime's capabilities");
    assert!(
        caps.1.contains("graphics"),
        "Vulkan needs the graphics capability"
    );
    let ignore = std::fs::read_to_string(repo(".dockerignore")).expect(".dockerignore");
    assert!(
        ignore.lines().any(|l| l.trim() == "target/"),
        "the build context leaves target/ out"
    );
    build_where_possible(&file);
}

/// Builds the image when asked to and a container tool reaches its daemon.
fn build_where_possible(file: &Path) {
    if std::env::var("RELIEF_CONTAINER_BUILD").as_deref() != Ok("1") {
        return;
    }
    let tool = ["docker", "podman"].into_iter().find(|t| {
        Command::new(t)
            .arg("info")
            .output()
            .is_ok_and(|o| o.status.success())
    });
    let Some(tool) = tool else {
        println!(
            "SKIPPED: RELIEF_CONTAINER_BUILD=1 but neither docker nor podman reaches a daemon"
        );
        return;
    };
    let root = env!("CARGO_MANIFEST_DIR");
    let args = [
        "build",
        "-f",
        file.to_str().unwrap(),
        "-t",
        "relief-test",
        root,
    ];
    run(tool, &args, &[]);
}
