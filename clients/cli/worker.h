// `granulab worker`: runs one job of a granulabd whose jobs go to a Slurm cluster (worker.cpp).
#pragma once

namespace granulab::cli {

/// `granulab worker --server URL --job ID [--patience S]`, the job's secret in GRANULAB_WORKER_TOKEN;
/// what a Slurm job of granulabd runs (server/slurm/). Returns the process's exit status.
int run_worker(int argc, char** argv);

}  // namespace granulab::cli
