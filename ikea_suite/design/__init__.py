"""Model-making code: parametric furniture families written as blueprints, and the MJCF writer."""
