"""The bench's own forms of the seven catalogue effects, written from the physics, one module each."""
