// The CLI lands in the next commit.
