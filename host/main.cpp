// photoncl command line (placeholder until the subcommands land).
#include <cstdio>
int main() { std::puts("photoncl"); return 0; }
