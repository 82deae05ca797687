# shellcheck shell=bash
# Sourced by parallel_matrix.sh and slurm_matrix.sh: matrix_out_dir COMMAND... prints the value of the
# matrix command's --out (as "--out DIR" or "--out=DIR"; the last one wins), or nothing when it has none.
matrix_out_dir() {
  local out="" args=("$@") i
  for ((i = 0; i < ${#args[@]}; ++i)); do
    [ "${args[$i]}" = "--out" ] && out=${args[$((i + 1))]:-}
    case "${args[$i]}" in --out=*) out=${args[$i]#--out=} ;; esac
  done
  printf '%s' "$out"
}
