#include "service/Cli.h"

int main(int argc, char** argv) {
  return service::runCli(argc, argv);
}
