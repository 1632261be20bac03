//! Colour science: observers (x̄ȳz̄), XYZ integration, RGB spaces. (in progress)
