// The CLI lands in the next commit.
int main() { return 1; }
