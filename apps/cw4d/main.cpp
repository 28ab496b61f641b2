// The cw4d command line: cw4d::cli::run (run.cpp) does everything.
#include "run.hpp"

int main(int argc, char** argv) {
  return cw4d::cli::run(argc, argv);
}
