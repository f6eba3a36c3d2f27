#!/usr/bin/env bash
# Compiles the device programs (platforms/common/kernels) as CUDA code with nvcc, in single,
# mixed and double precision, without a GPU: OpenMM compiles them only when a CUDA Context is
# made, so a machine without one would otherwise never see a CUDA compile error.  The prelude
# gives the common compute API's CUDA definitions as OpenMM's CUDA platform does; the programs
# are those the plugin assembles (compileDPDProgram and its callers).
#
#     bash scripts/check_cuda_kernels.sh [path/to/nvcc]
set -euo pipefail
nvcc=${1:-/usr/local/cuda/bin/nvcc}
root=$(cd "$(dirname "$0")/.." && pwd)
kernels=$root/platforms/common/kernels
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

prelude() {  # $1: the mixed type, $2: the real type
    cat <<EOF
#define KERNEL extern "C" __global__
#define DEVICE __device__
#define LOCAL __shared__
#define LOCAL_ARG
#define GLOBAL
#define RESTRICT __restrict__
#define LOCAL_ID threadIdx.x
#define LOCAL_SIZE blockDim.x
#define GLOBAL_ID (blockIdx.x*blockDim.x+threadIdx.x)
#define GLOBAL_SIZE (blockDim.x*gridDim.x)
#define GROUP_ID blockIdx.x
#define NUM_GROUPS gridDim.x
#define SYNC_THREADS __syncthreads();
#define MEM_FENCE __threadfence_block();
#define ATOMIC_ADD(dest, value) atomicAdd(dest, value)
typedef long long mm_long;
typedef unsigned long long mm_ulong;
typedef $2 real; typedef ${2}2 real2; typedef ${2}3 real3; typedef ${2}4 real4;
typedef $1 mixed; typedef ${1}2 mixed2; typedef ${1}3 mixed3; typedef ${1}4 mixed4;
#define make_real4 make_${2}4
#define make_mixed4 make_${1}4
#define make_mixed2 make_${1}2
#define OPENMMDPD_DEVICE_CODE 1
#define TWO_PI 6.283185307179586
#define CELL_SCAN_BLOCK 128
EOF
}

programs=("dynamics:philox cellList positionStrain leesEdwards dpdPairs dpdvv denOtterClarke"
          "edpd:philox cellList positionStrain leesEdwards dpdvv edpd"
          "sweeps:philox cellList positionStrain leesEdwards dpdvv pairConstraints sweep staggered"
          "soft:cellList softRepulsion" "mdpd:cellList mdpd" "random:philox pairRandomCheck")
failed=0
for program in "${programs[@]}"; do
    for precision in "float float single" "double float mixed" "double double double"; do
        set -- $precision
        source=$work/${program%%:*}-$3.cu
        { [ "$3" = mixed ] && echo "#define OPENMMDPD_MIXED 1"; prelude "$1" "$2"
          cat "$root/platforms/core/include/openmmdpd/PairFormulas.h" "$kernels/utilities.cc"
          for file in ${program#*:}; do cat "$kernels/$file.cc"; done; } > "$source"
        if ! "$nvcc" -arch=sm_75 -Wno-deprecated-declarations -c "$source" -o "$work/out.o" 2> "$work/log"; then
            echo "check_cuda_kernels: ${program%%:*} ($3 precision) does not compile:"; grep -m 10 error "$work/log"
            failed=1
        fi
    done
done
[ $failed = 0 ] && echo "check_cuda_kernels: ${#programs[@]} programs compile as CUDA in single, mixed and double precision"
exit $failed
