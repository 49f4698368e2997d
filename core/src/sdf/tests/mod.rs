mod mc;
