#!/usr/bin/env python3
"""Checks packaging/k8s/atelier-indexed-job.yaml and its Dockerfile without a cluster.

The Job is checked against the parts of the Kubernetes batch/v1 Job schema it uses (field
names and types at every level we write, so a misspelt or misplaced key fails), and for what
makes it an Atelier batch: Indexed completion, the --shard count equal to `completions`, the
index taken from JOB_COMPLETION_INDEX, a restart policy that lets a pod resume. The Dockerfile
is checked for a Debian base, a build from this tree and an atelier-cli it can run.

    packaging/k8s/check_job.py [JOB.yaml] [Dockerfile]
"""
import re
import sys
from pathlib import Path

try:
    import yaml
except ImportError:
    print("SKIP: python3-yaml is not installed (Debian: apt-get install python3-yaml)")
    sys.exit(77)

HERE = Path(__file__).resolve().parent

# The Job schema as far as the file uses it: dict = object with these keys (others refused),
# [x] = list of x, a type = a scalar of that type.
QUANTITY = (str, int)
CONTAINER = {
    "name": str, "image": str, "imagePullPolicy": str, "command": [str], "args": [str],
    "env": [{"name": str, "value": str}], "workingDir": str,
    "resources": {"requests": {"cpu": QUANTITY, "memory": QUANTITY},
                  "limits": {"cpu": QUANTITY, "memory": QUANTITY}},
    "volumeMounts": [{"name": str, "mountPath": str, "readOnly": bool, "subPath": str}],
}
LABELS = {"app.kubernetes.io/name": str}
SCHEMA = {
    "apiVersion": str, "kind": str,
    "metadata": {"name": str, "namespace": str, "labels": LABELS},
    "spec": {
        "completionMode": str, "completions": int, "parallelism": int, "backoffLimit": int,
        "backoffLimitPerIndex": int, "activeDeadlineSeconds": int,
        "ttlSecondsAfterFinished": int,
        "template": {
            "metadata": {"labels": LABELS},
            "spec": {
                "restartPolicy": str, "containers": [CONTAINER],
                "volumes": [{"name": str, "persistentVolumeClaim": {"claimName": str},
                             "emptyDir": {}}],
            },
        },
    },
}


def check(value, schema, path, errors):
    if isinstance(schema, dict):
        if not isinstance(value, dict):
            errors.append(f"{path}: must be an object")
            return
        for key, item in value.items():
            if key not in schema:
                errors.append(f"{path}/{key}: not a field here")
            else:
                check(item, schema[key], f"{path}/{key}", errors)
    elif isinstance(schema, list):
        if not isinstance(value, list):
            errors.append(f"{path}: must be a list")
            return
        for i, item in enumerate(value):
            check(item, schema[0], f"{path}/{i}", errors)
    elif not isinstance(value, schema) or isinstance(value, bool) and schema is not bool:
        errors.append(f"{path}: wrong type {type(value).__name__}")


def check_job(path):
    errors = []
    docs = [d for d in yaml.safe_load_all(path.read_text()) if d is not None]
    if len(docs) != 1:
        return [f"{path}: expected one document, found {len(docs)}"]
    job = docs[0]
    check(job, SCHEMA, "", errors)
    if errors:
        return [f"{path}: {e}" for e in errors]
    spec = job["spec"]
    want = [
        (job["apiVersion"] == "batch/v1", "apiVersion must be batch/v1"),
        (job["kind"] == "Job", "kind must be Job"),
        (spec.get("completionMode") == "Indexed", "spec.completionMode must be Indexed"),
        (spec.get("completions", 0) >= 1, "spec.completions must be at least 1"),
        (1 <= spec.get("parallelism", 1) <= spec.get("completions", 0),
         "spec.parallelism must be between 1 and completions"),
        (spec["template"]["spec"].get("restartPolicy") in ("Never", "OnFailure"),
         "restartPolicy must be Never or OnFailure (a Job's pods end)"),
    ]
    errors += [message for ok, message in want if not ok]
    containers = spec["template"]["spec"]["containers"]
    line = " ".join(containers[0].get("command", []) + containers[0].get("args", []))
    shard = re.search(r'--shard\s+"?\$\{?JOB_COMPLETION_INDEX\}?/(\d+)"?', line)
    if "atelier-cli batch" not in line:
        errors.append("the container must run atelier-cli batch")
    if not shard:
        errors.append("--shard must be ${JOB_COMPLETION_INDEX}/N")
    elif int(shard.group(1)) != spec["completions"]:
        errors.append(f"--shard count {shard.group(1)} differs from completions "
                      f"{spec['completions']}")
    mounts = {m["name"] for m in containers[0].get("volumeMounts", [])}
    volumes = {v["name"] for v in spec["template"]["spec"].get("volumes", [])}
    if mounts - volumes:
        errors.append(f"volume mounts without a volume: {sorted(mounts - volumes)}")
    return [f"{path}: {e}" for e in errors]


def check_dockerfile(path):
    text = path.read_text()
    errors = []
    froms = re.findall(r"^FROM\s+(\S+)", text, re.M)
    if not froms or any(not f.startswith("debian:") for f in froms):
        errors.append("every stage must start FROM a Debian image")
    root = HERE.parent.parent
    for source in re.findall(r"^COPY\s+(?!--from)(\S+)\s", text, re.M):
        if not (root / source).exists():
            errors.append(f"COPY {source}: not in the source tree")
    if "packaging/install-deps.sh" not in text:
        errors.append("build dependencies must come from packaging/install-deps.sh")
    if "atelier-cli" not in text:
        errors.append("the image must hold atelier-cli")
    return [f"{path}: {e}" for e in errors]


def main():
    job = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE / "atelier-indexed-job.yaml"
    docker = Path(sys.argv[2]) if len(sys.argv) > 2 else HERE / "Dockerfile"
    errors = check_job(job) + check_dockerfile(docker)
    for e in errors:
        print(e, file=sys.stderr)
    if errors:
        return 1
    print(f"{job.name} and {docker.name}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
