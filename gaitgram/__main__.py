from gaitgram.cli import main

main()
