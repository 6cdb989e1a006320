#!/bin/bash
# Renders on Kubernetes: the volume, the Indexed Job of shares, then (Kubernetes has no
# dependency between Jobs) the merge Job once every share is done. Needs kubectl pointed at a
# cluster that can pull the image built from deploy/k8s/Dockerfile.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
kubectl apply -f "$here/volume.yaml"
kubectl apply -f "$here/render-job.yaml"
kubectl wait --for=condition=complete --timeout=24h job/raydiance-render
kubectl apply -f "$here/merge-job.yaml"
kubectl wait --for=condition=complete --timeout=1h job/raydiance-merge
kubectl logs job/raydiance-merge
