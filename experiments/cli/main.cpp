#include "experiments/cli/cli.hpp"

int main(int argc, char** argv) { return lgvi::experiments::run_cli(argc, argv); }
