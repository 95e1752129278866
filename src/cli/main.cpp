// pfill's command line (placeholder entry until the subcommands land).
#include <iostream>
int main() { std::cout << "pfill\n"; return 0; }
