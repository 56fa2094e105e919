"""A minimal scene, from files of its own (schema, scene, theory), for tests/test_minimal_scene.py."""
