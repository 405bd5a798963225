//! A sharded precompute from the command line: the plan, shard tasks that take their index from
//! a batch engine's variable, the gather into the one-machine file, and the jobs `farm` writes
//! for Slurm and Kubernetes (submitting them to a real Slurm is `.ci/farm`'s).

use std::path::Path;
use std::process::{Command, Output};

mod common;
use common::{SCENE, scratch};

fn vcuts(cwd: &Path, env: &[(&str, &str)], args: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_vcuts"));
    c.current_dir(cwd).args(args);
    for v in ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"] {
        c.env_remove(v);
    }
    c.envs(env.iter().copied()).output().unwrap()
}

fn ok(o: Output) -> String {
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{text}");
    text
}

fn fails(o: Output) -> String {
    let text = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!o.status.success(), "{text}");
    text
}

#[test]
fn shard_tasks_from_each_engine_gather_to_the_one_machine_file() {
    let s = scratch("cli-shards");
    let dir = s.0.clone();
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let base = ["-q", "precompute", "--scene", "scene.toml", "--estimate-seconds", "0.1", "--cache-dir", "cache"];
    fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [base, extra].concat()
    }
    ok(vcuts(&dir, &[], &with(&base, &["-o", "one.vcuts"])));
    let plan = ok(vcuts(&dir, &[], &with(&base, &["--plan", "3"])));
    assert!(plan.contains("plan_shards=3") && plan.contains("section=id:svc (object 0, chunk 0) "), "{plan}");
    // One task per engine's index variable: Slurm, Kubernetes, AWS Batch.
    for (i, var) in ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"].iter().enumerate() {
        let index = i.to_string();
        ok(vcuts(&dir, &[(var, &index)], &with(&base, &["-o", "out/s.vcuts", "--shard", "env/3"])));
        assert!(dir.join(format!("out/s.shard-{i}-of-3.vcuts")).exists());
    }
    let e = fails(vcuts(&dir, &[], &with(&base, &["-o", "out/s.vcuts", "--shard", "env/3"])));
    assert!(e.contains("SLURM_ARRAY_TASK_ID") && e.contains("array job"), "{e}");
    // Without -o the gather writes beside the shards, under the name they were made for.
    let files: Vec<String> = (0..3).map(|i| format!("out/s.shard-{i}-of-3.vcuts")).collect();
    let mut gather = vec!["precompute", "--gather"];
    gather.extend(files.iter().map(String::as_str));
    let text = ok(vcuts(&dir, &[], &gather));
    assert!(text.contains("gather_shards=3"), "{text}");
    assert!(std::fs::read(dir.join("out/s.vcuts")).unwrap() == std::fs::read(dir.join("one.vcuts")).unwrap());
    let e = fails(vcuts(&dir, &[], &["precompute", "--gather", &files[0], &files[2], "-o", "x.vcuts"]));
    assert!(e.contains("shard 1 of 3 owes") && e.contains("run these shards again: 1"), "{e}");
    assert!(!dir.join("x.vcuts").exists());
}

#[test]
fn farm_writes_a_slurm_array_with_its_gather_and_a_kubernetes_indexed_job() {
    let s = scratch("cli-farm");
    let dir = s.0.clone();
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let common = ["--shards", "3", "--max-running", "2", "--scene", "scene.toml", "-o", "out/s.vcuts", "--dir", "jobs"];
    let text = ok(vcuts(&dir, &[], &[&["farm", "slurm"][..], &common, &["--sbatch=--partition=cpu"]].concat()));
    assert!(text.contains("slurm_shards_script="), "{text}");
    let shards = std::fs::read_to_string(dir.join("jobs/shards.sbatch")).unwrap();
    for want in
        ["#SBATCH --array=0-2%2", "#SBATCH --partition=cpu", "--shard env/3", "--scene scene.toml", "shard-%a.log"]
    {
        assert!(shards.contains(want), "{want} not in\n{shards}");
    }
    let gather = std::fs::read_to_string(dir.join("jobs/gather.sbatch")).unwrap();
    assert!(gather.contains("precompute --gather") && gather.contains("s.shard-2-of-3.vcuts"), "{gather}");
    ok(vcuts(&dir, &[], &[&["farm", "kubernetes"][..], &common].concat()));
    let job = std::fs::read_to_string(dir.join("jobs/indexed-job.yaml")).unwrap();
    for want in ["completionMode: Indexed", "completions: 3", "parallelism: 2", "\"env/3\""] {
        assert!(job.contains(want), "{want} not in\n{job}");
    }
    assert!(dir.join("jobs/gather.yaml").exists());
    let e = fails(vcuts(&dir, &[], &["farm", "slurm", "--shards", "0", "--scene", "scene.toml"]));
    assert!(e.contains("--shards") && e.contains("must be a whole number in [1, 1000000] shards"), "{e}");
    let e = fails(vcuts(&dir, &[], &["farm", "slurm", "--shards", "2", "--scene", "scene.toml", "--shard", "0/2"]));
    assert!(e.contains("the farm's to set"), "{e}");
}
