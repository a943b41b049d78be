"""filmscale.workflows: scene files, the `filmscale` command line, result store and plots."""
