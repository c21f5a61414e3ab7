#!/usr/bin/env bash
# Times PCL's pcl_normal_estimation -k 16 (normals only) against scanfill's features node (normals, curvatures,
# cross-field directions) on the same 10^6-point cloud, at 1 and 2 threads. Usage: bench/compare_pcl.sh BUILD_DIR
set -euo pipefail
build=${1:-build}
command -v pcl_normal_estimation >/dev/null || { echo "needs pcl-tools (apt-get install pcl-tools)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/bench/bench_cloud" 1000000 "$tmp/cloud.pcd"
for t in 1 2; do
  start=$(date +%s.%N)
  OMP_NUM_THREADS=$t pcl_normal_estimation "$tmp/cloud.pcd" "$tmp/normals.pcd" -k 16 >/dev/null
  end=$(date +%s.%N)
  echo "pcl_normal_estimation -k 16, $t thread(s): $(echo "$end - $start" | bc) s (includes reading and writing)"
done
"$build/bench/nodes_bench" --benchmark_filter='BM_Features/1000000' --benchmark_min_time=1
