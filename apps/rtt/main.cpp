#include <cstdio>
int main() { std::puts("rtt"); return 0; }
