"""gymmigrate: move legacy OpenAI Gym code to the Gymnasium 1.x API."""

__version__ = "0.1.0"
