"""Built-in case kinds, one module each; importing this package registers them all."""
