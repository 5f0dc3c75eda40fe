"""tidyplan: continual task planning for a service robot that tidies a room."""

__version__ = "0.1.0"
