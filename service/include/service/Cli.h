#pragma once
// The `hlodr` command line: one table of subcommands (Cli.cpp), each implemented in
// service/src/cmd/<Name>Command.cpp as `int run<Name>(const std::vector<std::string>& args)`.
#include <string>
#include <vector>

namespace service {

struct Command {
  const char* name;
  const char* summary;  // one line for `hlodr help`
  const char* usage;    // full help text for `hlodr help NAME` / `hlodr NAME --help`
  int (*run)(const std::vector<std::string>& args);
};

const std::vector<Command>& commands();

// Entry point of the executable; returns the process exit code (0 ok, 1 failure, 2 usage).
int runCli(int argc, char** argv);

}  // namespace service
