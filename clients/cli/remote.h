// The CLI's commands that talk to a granulabd server over HTTP: submit, status, wait, results,
// cancel, priority, delete, list. The server comes from --server URL or GRANULAB_SERVER (default http://127.0.0.1:8080).
#pragma once

namespace granulab::cli {

/// Runs one remote command (argv[1] is the command); returns the process exit status.
int run_remote(int argc, char** argv);

}  // namespace granulab::cli
