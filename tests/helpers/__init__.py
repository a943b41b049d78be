"""What several test modules share: scene texts, synthetic curves, instrument files, the
full-disk mount, a recorded engine. Test modules import from here, never from each other
(tests/test_test_layout.py), and nothing here imports a test module."""
