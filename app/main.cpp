// roverlab: command-line entry point. The subcommands are registered in
// app/commands.def; exit codes: 0 success, 2 usage error, 3 bad input, 4
// internal failure.
#include "app/command.h"

int main(int argc, char** argv) { return roverlab::app::run_command_line(argc, argv); }
