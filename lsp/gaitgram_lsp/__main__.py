from gaitgram_lsp.server import main

main()
